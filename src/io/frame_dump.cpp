#include "io/frame_dump.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"

namespace granudrag {

namespace fs = std::filesystem;

namespace {

const char* const kPosition = "/particles/frames/position";
const char* const kVelocity = "/particles/frames/velocity";

// "<name>.frames.<first>.h5" of `output` -> first; -1 when the name is not one of its segments.
long segment_first(const std::string& output_name, const std::string& name) {
  const std::string prefix = output_name + ".frames.", suffix = ".h5";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return -1;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.empty() ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return -1;
  return std::stol(digits);
}

fs::path directory_of(const std::string& output) {
  const fs::path dir = fs::path(output).parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

}  // namespace

std::vector<FrameDump::Segment> FrameDump::segments_of(const std::string& output) {
  std::vector<Segment> found;
  const std::string name = fs::path(output).filename().string();
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(directory_of(output), ec)) {
    const long first = segment_first(name, entry.path().filename().string());
    if (first >= 0) found.push_back({entry.path().string(), first});
  }
  std::sort(found.begin(), found.end(), [](const Segment& a, const Segment& b) { return a.first < b.first; });
  return found;
}

FrameDump::FrameDump(std::string output, const Particles& particles, long frames_kept)
    : output_(std::move(output)),
      n_(particles.size()),
      radius_(particles.radius),
      row_(3 * particles.size()) {
  species_.reserve(n_);
  for (Species s : particles.species) species_.push_back(static_cast<std::uint8_t>(s));
  // Segments written after the checkpoint (or by an earlier run, for a fresh one) are not
  // this run's: their frames are written again.
  long expected = 0;
  for (const Segment& s : segments_of(output_)) {
    if (s.first >= frames_kept) {
      fs::remove(s.path);
      continue;
    }
    if (s.first != expected) break;
    const h5::File f = h5::File::open(s.path);
    const h5::SeriesData d = f.read_series(kPosition);
    if (d.row_shape != std::vector<std::size_t>{n_, 3})
      throw Error("frame segment '" + s.path + "' holds frames of another run (not " + std::to_string(n_) +
                  " bodies); remove it and the checkpoint to start over");
    expected += static_cast<long>(d.rows());
  }
  if (expected != frames_kept) {
    std::ostringstream msg;
    msg << "the checkpoint of '" << output_ << "' counts " << frames_kept << " frames but the frame segments "
        << "on disk hold " << expected << " from the first on: '" << segment_path(expected)
        << "' is missing or damaged. Remove '" << output_ << ".checkpoint.h5' to start the run over";
    throw Error(msg.str());
  }
  std::error_code ec;
  fs::remove(segment_path(frames_kept) + ".tmp", ec);
  frames_ = frames_kept;
}

std::string FrameDump::segment_path(long first) const {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%08ld", first);
  return output_ + ".frames." + digits + ".h5";
}

void FrameDump::add(long step, double time, const Particles& p) {
  if (p.size() != n_)
    throw Error("a frame of " + std::to_string(p.size()) + " bodies in a dump of " + std::to_string(n_));
  if (!open_) {
    open_.emplace(h5::File::create(segment_path(frames_)));
    open_first_ = frames_;
    position_.emplace(open_->series(kPosition, {n_, 3}));
    velocity_.emplace(open_->series(kVelocity, {n_, 3}));
  }
  for (std::size_t i = 0; i < n_; ++i)
    for (int c = 0; c < 3; ++c) row_[3 * i + c] = p.x[i][c];
  position_->append(step, time, row_.data());
  for (std::size_t i = 0; i < n_; ++i)
    for (int c = 0; c < 3; ++c) row_[3 * i + c] = p.v[i][c];
  velocity_->append(step, time, row_.data());
  ++frames_;
}

void FrameDump::seal() {
  if (!open_) return;
  position_.reset();
  velocity_.reset();
  open_->set_attr("/particles/frames", "first_frame", static_cast<std::int64_t>(open_first_));
  open_->commit();
  open_.reset();
}

void FrameDump::write_into(h5::File& out) {
  seal();
  h5::Series position = out.series(kPosition, {n_, 3});
  h5::Series velocity = out.series(kVelocity, {n_, 3});
  long copied = 0;
  for (const Segment& s : segments_of(output_)) {
    if (s.first != copied) break;
    const h5::File f = h5::File::open(s.path);
    for (auto [group, series] : {std::pair{kPosition, &position}, std::pair{kVelocity, &velocity}}) {
      const h5::SeriesData d = f.read_series(group);
      for (std::size_t r = 0; r < d.rows(); ++r)
        series->append(d.steps[r], d.times[r], d.values.data() + r * d.columns);
    }
    copied += static_cast<long>(f.read_series(kPosition).rows());
  }
  if (copied != frames_)
    throw Error("frame segments of '" + output_ + "' hold " + std::to_string(copied) + " frames, not " +
                std::to_string(frames_) + ": '" + segment_path(copied) + "' is missing");
  out.write("/particles/frames/species/value", species_);
  out.write("/particles/frames/radius/value", radius_);
  out.set_attr("/particles/frames", "species_meaning",
               std::string("0 mobile grain, 1 frozen base grain, 2 intruder"));
}

std::vector<double> frame_times(const std::string& path) {
  const h5::File f = h5::File::open(path);
  if (!f.exists(std::string(kPosition) + "/time")) return {};
  return f.read_doubles(std::string(kPosition) + "/time");
}

void FrameDump::remove_segments() {
  for (const Segment& s : segments_of(output_)) fs::remove(s.path);
}

}  // namespace granudrag
