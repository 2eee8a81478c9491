#pragma once
// The simulation box: periodic in x and y, a flat wall at z = 0 (optional, for tests), open top.
#include <cmath>

#include "core/vec3.hpp"

namespace granudrag {

struct Box {
  double lx = 0, ly = 0;
  bool wall = true;

  // Valid for |d| < 1.5 L per component, which holds between neighbour-list rebuilds
  // because positions are wrapped at every rebuild and move less than a skin in between.
  Vec3 min_image(Vec3 d) const {
    const double hx = 0.5 * lx, hy = 0.5 * ly;
    if (d.x() > hx)
      d.x() -= lx;
    else if (d.x() < -hx)
      d.x() += lx;
    if (d.y() > hy)
      d.y() -= ly;
    else if (d.y() < -hy)
      d.y() += ly;
    return d;
  }
  void wrap(Vec3& p) const {
    p.x() -= lx * std::floor(p.x() / lx);
    p.y() -= ly * std::floor(p.y() / ly);
    // floor() of a tiny negative number gives exactly L after the subtraction.
    if (p.x() >= lx) p.x() -= lx;
    if (p.y() >= ly) p.y() -= ly;
  }
};

}  // namespace granudrag
