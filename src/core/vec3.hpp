#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace granudrag {
// Fixed-size, unaligned 3-vectors: Eigen generates straight-line code for them and
// std::vector<Vec3> needs no aligned allocator.
using Vec3 = Eigen::Vector3d;
}  // namespace granudrag
