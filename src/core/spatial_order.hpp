#pragma once
// An order of the bodies in which neighbours are near in index: a sweep along one axis in thin
// layers (a quarter diameter), and within a layer a Morton (Z-order) curve over cells of one
// diameter in the other two. The threaded force loop relies on such a one-dimensional sweep
// for its two-colour schedule (contact/verlet_contacts.cpp: a block's partners must not reach
// the rows another block of its colour writes); a bed in another order (imported from
// elsewhere) takes private force arrays and a reduction instead. Intruders stay last, in their
// order.
//
// The sweep's cross-section is what a step keeps in cache: the bodies within a contact's reach
// of the sweep front, which each row's partners (j > i) lie ahead of. Along z (bottom up, the
// order a pour leaves: protocol/pour.cpp places grains layer by layer) it is the box's whole
// area, lx ly; along the longer horizontal axis it is the other one times the bed's height. The
// horizontal sweep is periodic: the first layers' rows have partners in the last ones, across
// the boundary, which the colour check allows for.
#include <cstddef>
#include <vector>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

enum class SweepAxis {
  Auto,  // the longer horizontal axis when the bed is shallower than that axis is long, else z
  X,
  Y,
  Z,
};

// The axis Auto picks for p in box.
SweepAxis sweep_axis(const Particles& p, const Box& box);
// order[k]: the index in p of the body that goes to position k.
std::vector<std::size_t> spatial_order(const Particles& p, const Box& box, SweepAxis axis = SweepAxis::Auto);
// p's bodies in that order (every array, forces included).
Particles reordered(const Particles& p, const std::vector<std::size_t>& order);
// rank[order[k]] = k: where each body went.
std::vector<std::size_t> inverse_order(const std::vector<std::size_t>& order);

}  // namespace granudrag
