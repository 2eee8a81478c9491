// Pulls on a small bed: the observables' definitions, checkpoint/resume bitwise identical to an
// uninterrupted run, the stopping rule, and the refusals. The statistics of the series are in
// test_observables.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "helpers.hpp"
#include "protocol/observables.hpp"
#include "protocol/pull.hpp"

using namespace granudrag;

namespace {

using support::small_bed;

}  // namespace

TEST(Pull, FroudeNumberIsPaperEq4) { EXPECT_DOUBLE_EQ(froude_number(1.0, 4.0), 2.0 * std::sqrt(8.0) / 5.0); }

TEST(Pull, MeasuresDragAndContactsOfAMovingIntruder) {
  PullSpec spec;
  spec.speed = 1.0;
  spec.distance = 3.0;
  Pull pull(small_bed(), spec);
  pull.run(false);
  const PullResult r = pull.result();
  EXPECT_GT(r.drag, 0.0);  // resists the motion along +x
  EXPECT_NEAR(r.drag, -mean({pull.record().fx.begin() + r.transient_samples, pull.record().fx.end()}),
              1e-12 * r.drag);
  EXPECT_GT(r.drag_error, 0.0);
  EXPECT_LT(r.drag_error, r.drag);
  EXPECT_GT(r.coordination, 3.0);
  EXPECT_GT(r.coordination_error, 0.0);  // the intruder's contacts fluctuate
  EXPECT_LT(r.coordination_error, 0.5 * r.coordination);
  EXPECT_GT(r.theta, 0.0);
  EXPECT_LT(r.theta, M_PI / 2);  // contacts form in front of the intruder
  // theta's error: ratio_error of the angles' sums and counts per interval past the transient.
  std::vector<double> sums, counts;
  const PullRecord& rec = pull.record();
  for (std::size_t k = 0; k < rec.time.size(); ++k) {
    if (rec.time[k] <= r.transient_distance / spec.speed) continue;
    sums.push_back(rec.theta_sum_series[k] - (k ? rec.theta_sum_series[k - 1] : 0.0));
    counts.push_back(rec.theta_count_series[k] - (k ? rec.theta_count_series[k - 1] : 0.0));
  }
  const MeanError theta = ratio_error(sums, counts);
  EXPECT_NEAR(theta.mean, r.theta, 1e-12 * r.theta);
  EXPECT_EQ(theta.error, r.theta_error);
  EXPECT_EQ(theta.dof, r.theta_dof);
  EXPECT_GT(r.theta_error, 0.0);
  EXPECT_LT(r.theta_error, 0.2);
  EXPECT_EQ(rec.theta_count_series.back(), static_cast<double>(rec.theta_count));
  // The time-weighted theta: the contacts present at each sample past the transient, whose
  // count averages to n (n is the mean over every step, these over the samples' instants).
  ASSERT_EQ(rec.theta_present_sum.size(), rec.time.size());
  std::vector<double> present_sums, present_counts;
  for (std::size_t k = r.transient_samples; k < rec.time.size(); ++k) {
    present_sums.push_back(rec.theta_present_sum[k]);
    present_counts.push_back(rec.theta_present_count[k]);
    EXPECT_LE(rec.theta_present_sum[k], M_PI * rec.theta_present_count[k]);
  }
  const MeanError present = ratio_error(present_sums, present_counts);
  EXPECT_EQ(present.mean, r.theta_present);
  EXPECT_EQ(present.error, r.theta_present_error);
  EXPECT_GT(r.theta_present, 0.0);
  EXPECT_LT(r.theta_present, M_PI);
  EXPECT_GT(r.theta_present_error, 0.0);
  EXPECT_NEAR(mean(present_counts), r.coordination, 0.15 * r.coordination);
  EXPECT_GT(r.bulk_coordination, 2.0);
  EXPECT_LT(r.bulk_coordination, 8.0);
  double total = 0;
  for (double pz : r.z_distribution) total += pz;
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_NEAR(r.kappa, r.bulk_coordination / r.coordination * 9.0 / (2 * std::sqrt(3.0)), 1e-12);
  // The nested shells count the same samples: at the main shell's width (2 d) their Z is the
  // histogram's, accumulated separately; kappa follows Eq. 8 in each.
  ASSERT_EQ(r.shell_z.size(), CoordinationShells::widths.size());
  EXPECT_EQ(CoordinationShells::widths[3], spec.shell);
  EXPECT_NEAR(r.shell_z[3], r.bulk_coordination, 1e-12);
  for (std::size_t k = 0; k < r.shell_z.size(); ++k)
    EXPECT_NEAR(r.shell_kappa[k], r.shell_z[k] / r.coordination * 9.0 / (2 * std::sqrt(3.0)), 1e-12);
  EXPECT_GT(pull.record().shells.grains[0], 0);  // touching grains were seen
  EXPECT_EQ(pull.record().snapshots.size(), 3u);
  // The intruder moved exactly the requested distance (rounded up to whole samples).
  const Particles& p = pull.simulation().particles();
  const double travelled = pull.simulation().time() * spec.speed;
  EXPECT_GE(travelled, 3.0 - 1e-9);
  EXPECT_DOUBLE_EQ(p.x[small_bed().intruder].z(), small_bed().state.particles.x[small_bed().intruder].z());
  // Work done on the grains is the drag times the distance, up to the transient.
  EXPECT_NEAR(pull.record().work / travelled, -mean(pull.record().fx), 1e-9 * pull.record().work);
  // Its timing: the loop, and the second half of its steps (an active region's steady cost).
  const long steps = pull.simulation().steps_done();
  EXPECT_EQ(pull.loop_steps(), steps);
  const std::string timing = pull.timing_report();
  const std::size_t at = timing.find("\ntiming: second half ");
  ASSERT_NE(at, std::string::npos) << timing;
  double half_seconds = -1;
  long half_steps = -1;
  ASSERT_EQ(std::sscanf(timing.c_str() + at, "\ntiming: second half %lf s for %ld steps", &half_seconds,
                        &half_steps),
            2);
  EXPECT_EQ(half_steps, steps - steps / 2);
  EXPECT_GT(half_seconds, 0.0);
  EXPECT_LT(half_seconds, pull.loop_seconds());
}

TEST(Pull, ResumedFromCheckpointIsBitwiseIdentical) {
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.checkpoint_every = 500;
  Pull whole(small_bed(), spec);
  const support::Checkpoints checkpoints = support::run_keeping_checkpoints(whole);
  ASSERT_GE(checkpoints.size(), 2u);
  // "Kill" after the first checkpoint and resume from it.
  Pull resumed(small_bed(), spec, checkpoints[0].first, checkpoints[0].second);
  resumed.run(false, [](const Pull&) {});
  ASSERT_TRUE(support::same_motion(whole.simulation().particles(), resumed.simulation().particles()));
  EXPECT_EQ(whole.result().drag, resumed.result().drag);
  EXPECT_EQ(whole.record().fx, resumed.record().fx);
  EXPECT_EQ(whole.result().theta_error, resumed.result().theta_error);

  // From a record written before theta's series (an older checkpoint): theta is the same; its
  // error comes from the intervals after the resume, scaled to all the angles.
  const auto counted = std::find_if(checkpoints.begin(), checkpoints.end() - 1,
                                    [](const auto& c) { return c.second.theta_count > 0; });
  ASSERT_NE(counted, checkpoints.end() - 1) << "no checkpoint between the transient and the end";
  PullRecord old = counted->second;
  old.theta_sum_series.clear();
  old.theta_count_series.clear();
  Pull from_old(small_bed(), spec, counted->first, old);
  from_old.run(false, [](const Pull&) {});
  EXPECT_EQ(from_old.result().theta, whole.result().theta);
  EXPECT_GT(from_old.result().theta_error, 0.5 * whole.result().theta_error);
  EXPECT_LT(from_old.result().theta_error, 2.0 * whole.result().theta_error);
}

TEST(Pull, FramesComeAtStepZeroAndEveryDumpIntervalAndResumeWhereTheCheckpointCounted) {
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.checkpoint_every = 500;
  spec.dump_every = 300;
  Pull whole(small_bed(), spec);
  std::vector<long> steps;
  std::vector<std::vector<Vec3>> positions;
  std::vector<std::pair<Simulation::State, PullRecord>> checkpoints;
  whole.run(
      false, [&](const Pull& p) { checkpoints.emplace_back(p.state(), p.record()); },
      [&](const Pull& p) {
        steps.push_back(p.simulation().steps_done());
        positions.push_back(p.particles_in_bed_order().x);  // what the frames write
      });
  const long total = whole.record().total_steps;
  ASSERT_EQ(whole.record().frames, total / 300 + 1);
  for (std::size_t k = 0; k < steps.size(); ++k) EXPECT_EQ(steps[k], static_cast<long>(300 * k));
  EXPECT_EQ(positions.front(), small_bed().state.particles.x);  // frame 0 is the bed as poured
  EXPECT_EQ(positions.back() == whole.particles_in_bed_order().x, total % 300 == 0);
  // Resumed from the first checkpoint (step 500: frames 0 and 300 counted), the frames go on
  // from step 600, the same bit for bit.
  ASSERT_GE(checkpoints.size(), 1u);
  EXPECT_EQ(checkpoints[0].second.frames, 2);
  Pull resumed(small_bed(), spec, checkpoints[0].first, checkpoints[0].second);
  std::vector<long> resumed_steps;
  std::vector<std::vector<Vec3>> resumed_positions;
  // Checkpoints force list rebuilds, which a resumed run must do at the same steps.
  resumed.run(
      false, [](const Pull&) {},
      [&](const Pull& p) {
        resumed_steps.push_back(p.simulation().steps_done());
        resumed_positions.push_back(p.particles_in_bed_order().x);
      });
  EXPECT_EQ(resumed.record().frames, whole.record().frames);
  ASSERT_EQ(resumed_steps, std::vector<long>(steps.begin() + 2, steps.end()));
  for (std::size_t k = 0; k < resumed_positions.size(); ++k)
    EXPECT_EQ(resumed_positions[k], positions[k + 2]) << k;
}

TEST(Pull, ATargetErrorStopsThePullOnceTheDragIsThatPrecise) {
  PullSpec spec;
  // On this small periodic bed the drag decorrelates over 2-4 d of travel: 10 effective
  // samples, the rule's least, take 25-45 d, depending on the thread count (which changes the
  // trajectory's rounding, so its details).
  spec.speed = 3.0;
  spec.max_overlap = 0.2;  // soft grains at V = 3, as the default study sets
  spec.distance = 90.0;
  spec.target_error = 0.1;
  spec.min_distance = 2.0;
  Pull pull(small_bed(), spec);
  pull.run(false);
  const PullResult r = pull.result();
  const double travelled = pull.simulation().time() * spec.speed;
  EXPECT_EQ(pull.record().stop_reason, "target_error");
  EXPECT_LT(travelled, 90.0 - 10);  // stopped well before the distance
  EXPECT_GE(travelled, 2.0);        // not before min_distance
  EXPECT_EQ(pull.record().total_steps, pull.simulation().steps_done());
  // The result is computed over the samples the stopping rule saw: its error meets the target.
  EXPECT_LE(r.drag_error, 0.1 * r.drag);
  EXPECT_GE(r.drag_dof, 10);
  // Unmet, the same pull travels the whole distance and says so.
  spec.target_error = 1e-4;
  Pull whole(small_bed(), spec);
  whole.run(false);
  EXPECT_EQ(whole.record().stop_reason, "distance");
  EXPECT_GE(whole.simulation().time() * spec.speed, 90.0 - 1e-9);
  EXPECT_GT(whole.result().drag_error, 1e-4 * whole.result().drag);
  // The stopped pull is the first part of the whole one, sample for sample.
  const std::vector<double>& a = pull.record().fx;
  EXPECT_TRUE(std::equal(a.begin(), a.end(), whole.record().fx.begin()));
}

TEST(Pull, AResumedPullStopsAtTheSameStepAsAnUninterruptedOne) {
  PullSpec spec;
  spec.speed = 3.0;
  spec.max_overlap = 0.2;  // soft grains at V = 3, as the default study sets
  spec.distance = 90.0;
  spec.target_error = 0.1;
  spec.min_distance = 2.0;
  spec.checkpoint_every = 4000;
  Pull whole(small_bed(), spec);
  const support::Checkpoints checkpoints = support::run_keeping_checkpoints(whole);
  ASSERT_EQ(whole.record().stop_reason, "target_error");
  // Resumed from the last checkpoint but one (32,000 of the 39,264 steps, 9 checkpoints): the
  // resumed pull restarts the series and the stopping checks from the record, and meets the
  // stop a few checks later. From the second checkpoint it took 149 s under the sanitizers on
  // the slower 2-core machine (tools/test.sh); this way it steps 7,264 steps again, not 31,264.
  ASSERT_GE(checkpoints.size(), 3u);
  const auto& from = checkpoints[checkpoints.size() - 2];
  Pull resumed(small_bed(), spec, from.first, from.second);
  resumed.run(false, [](const Pull&) {});
  EXPECT_EQ(resumed.record().stop_reason, "target_error");
  EXPECT_EQ(resumed.simulation().steps_done(), whole.simulation().steps_done());
  EXPECT_EQ(resumed.record().fx, whole.record().fx);
  EXPECT_EQ(resumed.result().drag, whole.result().drag);
}

TEST(Pull, StoppingChecksAreSparseAndFallOnFixedSampleCounts) {
  long checks = 0;
  for (long n = 1; n <= 100000; ++n) checks += stopping_check_due(n);
  EXPECT_FALSE(stopping_check_due(15));
  EXPECT_TRUE(stopping_check_due(16));
  EXPECT_GT(checks, 16 * 12);  // 16 per doubling from 16 to 1e5 (12.6 doublings)
  EXPECT_LT(checks, 16 * 14);
  EXPECT_TRUE(stopping_check_due(1024) && stopping_check_due(1088) && !stopping_check_due(1089));
}

TEST(Pull, ABlowUpStopsTheRunWithAMessage) {
  Bed broken = small_bed();
  broken.state.particles.v[0] = Vec3(NAN, 0, 0);  // a NaN that will spread through contacts
  PullSpec spec;
  spec.distance = 1.0;
  int checkpoints = 0;
  Pull pull(broken, spec);
  try {
    pull.run(false, [&](const Pull&) { ++checkpoints; });
    FAIL() << "a NaN velocity ran to the end";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(msg.find("blew up") != std::string::npos || msg.find("non-finite") != std::string::npos)
        << msg;
  }
  EXPECT_EQ(checkpoints, 0);  // nothing bad was checkpointed
}

TEST(Pull, RejectsBadInput) {
  PullSpec spec;
  spec.speed = -1;
  EXPECT_THROW(Pull(small_bed(), spec), Error);
  spec = PullSpec{};
  spec.target_error = 2;  // a relative error above 1
  EXPECT_THROW(Pull(small_bed(), spec), Error);
  spec.target_error = 0.05;
  spec.distance = 3;
  spec.min_distance = 3;  // the target could never stop it
  try {
    Pull(small_bed(), spec);
    FAIL() << "min_distance = distance accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("min_distance"), std::string::npos) << e.what();
  }
  Bed no_intruder = small_bed();
  no_intruder.intruder = -1;
  EXPECT_THROW(Pull(no_intruder, PullSpec{}), Error);
}

TEST(Pull, ABedWhoseGrainsOverlapBeyondTheGuardIsRefusedWithThatReason) {
  Bed bed = small_bed();
  Particles& p = bed.state.particles;
  std::size_t a = 0;
  while (p.species[a] != Species::Mobile) ++a;
  std::size_t b = a + 1;  // the nearest other grain, moved onto a to overlap it by 0.3 d
  for (std::size_t k = 0; k < p.size(); ++k)
    if (k != a && p.species[k] == Species::Mobile &&
        bed.box.min_image(p.x[k] - p.x[a]).norm() < bed.box.min_image(p.x[b] - p.x[a]).norm())
      b = k;
  const Vec3 along = bed.box.min_image(p.x[b] - p.x[a]).normalized();
  p.x[b] = p.x[a] + along * (p.radius[a] + p.radius[b] - 0.3);
  try {
    Pull pull(bed, PullSpec{});
    FAIL() << "accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("overlapping by 0.3"), std::string::npos) << m;
    EXPECT_NE(m.find("damaged"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(Pull(small_bed(), PullSpec{}));
}

TEST(Pull, ASpeedTheBedCannotResolveIsRefusedBeforeAnyStep) {
  PullSpec spec;
  spec.speed = 1e6;  // ran to the end with NaN before the speed limits
  try {
    Pull pull(small_bed(), spec);
    FAIL() << "V = 1e6 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the largest speed that works is"), std::string::npos) << e.what();
  }
}

TEST(Pull, AnOverlapOverTheBoundStopsTheRunOrIsRecordedWithKeepGoing) {
  // V = 6 passes the impact estimate at kn = 2e4 (largest speed 6.6) but the bed, loaded from
  // behind, overlaps the grain ahead of the intruder by 0.113 d: the guard stops it.
  PullSpec spec;
  spec.speed = 6;
  spec.distance = 1.0;
  int checkpoints = 0;
  {
    Pull pull(small_bed(), spec);
    try {
      pull.run(false, [&](const Pull&) { ++checkpoints; });
      FAIL() << "an overlap over 0.1 d ran to the end";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("exceeds max_overlap = 0.1 d"), std::string::npos) << e.what();
    }
  }
  spec.keep_going = true;
  Pull pull(small_bed(), spec);
  pull.run(false);
  EXPECT_TRUE(pull.finished());
  EXPECT_NE(pull.verdict().find("exceeds max_overlap"), std::string::npos) << pull.verdict();
  EXPECT_GT(pull.record().max_overlap, 0.1);
  // A larger bound passes the same pull clean.
  spec.keep_going = false;
  spec.max_overlap = 0.2;
  Pull clean(small_bed(), spec);
  clean.run(false);
  EXPECT_EQ(clean.verdict(), "clean");
}

TEST(Pull, AReplicaStartsFromTheSameBedWithOneGrainNudgedAndResumesBitwise) {
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.checkpoint_every = 500;
  Pull plain(small_bed(), spec);
  PullSpec nudged = spec;
  nudged.perturbation = 1e-6;
  Pull replica(small_bed(), nudged);
  // Before any step: the two differ in one velocity component, by the perturbation, of the
  // mobile grain nearest the intruder.
  const Particles& a = plain.simulation().particles();
  const Particles& b = replica.simulation().particles();
  const int g = replica.replica_grain();
  ASSERT_EQ(a.species[g], Species::Mobile);
  const Box box = small_bed().box;
  const Vec3 centre = a.x[replica.intruder()];
  const double nearest = box.min_image(a.x[g] - centre).norm();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a.species[i] == Species::Mobile) {
      ASSERT_GE(box.min_image(a.x[i] - centre).norm(), nearest) << i;
    }
    ASSERT_EQ(a.x[i], b.x[i]) << i;
    if (static_cast<int>(i) != g) {
      ASSERT_EQ(a.v[i], b.v[i]) << i;
    }
  }
  EXPECT_NEAR(b.v[g].x() - a.v[g].x(), 1e-6, 1e-15);
  EXPECT_EQ(b.v[g].y(), a.v[g].y());
  // The replica parts from the pull (chaos), and resumes bitwise like any pull: a resumed
  // replica is not nudged a second time.
  plain.run(false);
  const support::Checkpoints checkpoints = support::run_keeping_checkpoints(replica);
  EXPECT_NE(plain.result().drag, replica.result().drag);
  ASSERT_GE(checkpoints.size(), 1u);
  Pull resumed(small_bed(), nudged, checkpoints[0].first, checkpoints[0].second);
  resumed.run(false, [](const Pull&) {});
  EXPECT_EQ(resumed.result().drag, replica.result().drag);
  EXPECT_EQ(resumed.record().fx, replica.record().fx);
}
