#include "contact/neighbor_list.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace granudrag {

namespace {

// Cell indices within `reach` of a coordinate along a periodic axis, each once even when the
// reach wraps around a short axis.
void periodic_cells(double coord, double reach, double cell, int n, std::vector<int>& out) {
  out.clear();
  const int lo = static_cast<int>(std::floor((coord - reach) / cell));
  const int hi = static_cast<int>(std::floor((coord + reach) / cell));
  if (hi - lo + 1 >= n) {
    for (int c = 0; c < n; ++c) out.push_back(c);
    return;
  }
  for (int c = lo; c <= hi; ++c) out.push_back(((c % n) + n) % n);
}

// Wraps the positions into the box and records them as the build's reference, in one parallel
// pass; a body with a non-finite position stops the run (the first such body is named).
void wrap_and_record(Particles& p, const Box& box, std::vector<Vec3>& x_at_build) {
  const long n = static_cast<long>(p.size());
  x_at_build.resize(p.size());
  long bad = n;
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (long i = 0; i < n; ++i) {
    if (!p.x[i].allFinite()) {
      bad = std::min(bad, i);
      continue;
    }
    box.wrap(p.x[i]);
    x_at_build[i] = p.x[i];
  }
  if (bad < n) {
    std::ostringstream msg;
    msg << "particle " << bad << " has a non-finite position: the run became unstable "
        << "(time step too large for the stiffness, or overlapping initial particles)";
    throw Error(msg.str());
  }
}

}  // namespace

int NeighborList::Grid::cell_z(double z) const {
  const int c = static_cast<int>((z - z0) / cz);
  return std::clamp(c, 0, nz - 1);
}

bool NeighborList::rebuild_due(std::size_t n, double max_drift_sq) const {
  if (builds_ == 0 || x_at_build_.size() != n) return true;
  const double limit = 0.25 * skin_ * skin_;  // (skin/2)^2: two bodies approach by < skin
  return !(max_drift_sq <= limit);
}

void NeighborList::build(Particles& p, const Box& box) {
  wrap_and_record(p, box, x_at_build_);
  std::swap(grain_, grain_prev_);
  std::swap(intruder_, intruder_prev_);

  const long n = static_cast<long>(p.size());
  double rmax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : rmax)
  for (long i = 0; i < n; ++i)
    if (p.species[i] != Species::Intruder) rmax = std::max(rmax, p.radius[i]);
  const double cell = 2.0 * rmax + skin_;
  auto reach = [&](long i) {
    return (p.species[i] == Species::Intruder ? p.radius[i] : rmax) + rmax + skin_;
  };
  long too_big = n;  // the first body that would meet its own periodic image
#pragma omp parallel for schedule(static) reduction(min : too_big)
  for (long i = 0; i < n; ++i)
    if (2.0 * reach(i) + skin_ > std::min(box.lx, box.ly)) too_big = std::min(too_big, i);
  if (too_big < n) {
    std::ostringstream msg;
    msg << "box " << box.lx << " x " << box.ly << " is too small: particle " << too_big << " of radius "
        << p.radius[too_big] << " would meet its own periodic image; Lx and Ly must"
        << " exceed " << 2.0 * reach(too_big) + skin_;
    throw Error(msg.str());
  }
  bin(p, box, cell);
  build_grain_pairs(p, box, rmax);
  build_intruder_pairs(p, box, rmax);
  ++builds_;
}

void NeighborList::bin(const Particles& p, const Box& box, double cell) {
  Grid& g = grid_;
  g.nx = std::max(1, static_cast<int>(box.lx / cell));
  g.ny = std::max(1, static_cast<int>(box.ly / cell));
  g.cx = box.lx / g.nx;
  g.cy = box.ly / g.ny;
  const long n = static_cast<long>(p.size());
  double zmin = HUGE_VAL, zmax = -HUGE_VAL;
#pragma omp parallel for schedule(static) reduction(min : zmin) reduction(max : zmax)
  for (long i = 0; i < n; ++i) {
    if (p.species[i] == Species::Intruder) continue;
    zmin = std::min(zmin, p.x[i].z());
    zmax = std::max(zmax, p.x[i].z());
  }
  if (zmin > zmax) zmin = zmax = 0.0;  // no grains
  g.z0 = zmin;
  g.cz = cell;
  const double layers = (zmax - zmin) / cell;
  if (layers * g.nx * g.ny > 2e7 || !std::isfinite(layers))
    throw Error("a grain flew " + std::to_string(zmax - zmin) +
                " grain diameters away from the bed: the run became unstable (check dt and the "
                "initial overlaps)");
  g.nz = static_cast<int>(layers) + 1;

  const std::size_t ncells = static_cast<std::size_t>(g.nx) * g.ny * g.nz;
  g.start.assign(ncells + 1, 0);
  std::vector<int>& cell_of = cell_of_;
  cell_of.resize(p.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    if (p.species[i] == Species::Intruder) {
      cell_of[i] = -1;
      continue;
    }
    const int ix = std::min(g.nx - 1, static_cast<int>(p.x[i].x() / g.cx));
    const int iy = std::min(g.ny - 1, static_cast<int>(p.x[i].y() / g.cy));
    cell_of[i] = (g.cell_z(p.x[i].z()) * g.ny + iy) * g.nx + ix;
  }
  for (long i = 0; i < n; ++i)
    if (cell_of[i] >= 0) ++g.start[cell_of[i] + 1];
  for (std::size_t c = 0; c < ncells; ++c) g.start[c + 1] += g.start[c];
  g.items.resize(g.start[ncells]);
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (cell_of[i] >= 0) g.items[fill[cell_of[i]]++] = static_cast<int>(i);
}

void NeighborList::build_grain_pairs(const Particles& p, const Box& box, double rmax) {
  const Grid& g = grid_;
  const long n = static_cast<long>(p.size());
  std::vector<std::vector<int>>& chunks = chunks_;  // kept: their memory is reused next build
  if (static_cast<int>(chunks.size()) < omp_get_max_threads()) chunks.resize(omp_get_max_threads());
  grain_.offset.assign(n + 1, 0);
  wrapping_rows_.assign(n, 0);
  const double half_x = 0.5 * box.lx, half_y = 0.5 * box.ly;

#pragma omp parallel
  {
    // Contiguous blocks of rows per thread: concatenating the chunks in thread order gives
    // the rows in order, whatever the thread count.
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const long i0 = n * t / nt, i1 = n * (t + 1) / nt;
    std::vector<int>& out = chunks[t];
    out.clear();
    std::vector<int> xs, ys;
    for (long i = i0; i < i1; ++i) {
      if (p.species[i] == Species::Intruder) continue;
      const Vec3& xi = p.x[i];
      const bool frozen_i = p.species[i] == Species::Frozen;
      periodic_cells(xi.x(), rmax * 2 + skin_, g.cx, g.nx, xs);
      periodic_cells(xi.y(), rmax * 2 + skin_, g.cy, g.ny, ys);
      const int iz = g.cell_z(xi.z());
      const std::size_t row_start = out.size();
      bool wraps = false;
      for (int cz = std::max(0, iz - 1); cz <= std::min(g.nz - 1, iz + 1); ++cz) {
        for (int cy : ys) {
          for (int cx : xs) {
            const int c = (cz * g.ny + cy) * g.nx + cx;
            for (int k = g.start[c]; k < g.start[c + 1]; ++k) {
              const int j = g.items[k];
              if (j <= i || (frozen_i && p.species[j] == Species::Frozen)) continue;
              const double cut = p.radius[i] + p.radius[j] + skin_;
              if (box.min_image(xi - p.x[j]).squaredNorm() < cut * cut) {
                out.push_back(j);
                wraps |= std::abs(xi.x() - p.x[j].x()) > half_x || std::abs(xi.y() - p.x[j].y()) > half_y;
              }
            }
          }
        }
      }
      wrapping_rows_[i] = wraps;
      std::sort(out.begin() + row_start, out.end());
      grain_.offset[i + 1] = static_cast<int>(out.size() - row_start);
    }
#pragma omp barrier
#pragma omp single
    {
      for (long i = 0; i < n; ++i) grain_.offset[i + 1] += grain_.offset[i];
      grain_.partner.resize(grain_.offset[n]);
    }  // (implied barrier)
    std::copy(out.begin(), out.end(), grain_.partner.begin() + grain_.offset[i0]);
  }
}

void NeighborList::build_intruder_pairs(const Particles& p, const Box& box, double rmax) {
  const Grid& g = grid_;
  intruder_bodies_.clear();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == Species::Intruder) intruder_bodies_.push_back(static_cast<int>(i));
  intruder_.offset.assign(1, 0);
  intruder_.partner.clear();
  std::vector<int> xs, ys;
  for (int body : intruder_bodies_) {
    const Vec3& xb = p.x[body];
    const double reach = p.radius[body] + rmax + skin_;
    periodic_cells(xb.x(), reach, g.cx, g.nx, xs);
    periodic_cells(xb.y(), reach, g.cy, g.ny, ys);
    const int z_lo = static_cast<int>(std::floor((xb.z() - reach - g.z0) / g.cz));
    const int z_hi = static_cast<int>(std::floor((xb.z() + reach - g.z0) / g.cz));
    const std::size_t row_start = intruder_.partner.size();
    for (int cz = std::max(0, z_lo); cz <= std::min(g.nz - 1, z_hi); ++cz)
      for (int cy : ys)
        for (int cx : xs) {
          const int c = (cz * g.ny + cy) * g.nx + cx;
          for (int k = g.start[c]; k < g.start[c + 1]; ++k) {
            const int j = g.items[k];
            const double cut = p.radius[body] + p.radius[j] + skin_;
            if (box.min_image(xb - p.x[j]).squaredNorm() < cut * cut) intruder_.partner.push_back(j);
          }
        }
    std::sort(intruder_.partner.begin() + row_start, intruder_.partner.end());
    intruder_.offset.push_back(static_cast<int>(intruder_.partner.size()));
  }
}

}  // namespace granudrag
