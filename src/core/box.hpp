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
    d.x() = min_image(d.x(), lx);
    d.y() = min_image(d.y(), ly);
    return d;
  }
  // One component along a periodic axis of length l (for loops that work in plain doubles).
  static double min_image(double d, double l) {
    const double h = 0.5 * l;
    return d > h ? d - l : (d < -h ? d + l : d);
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
