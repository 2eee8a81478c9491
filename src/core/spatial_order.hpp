#pragma once
// An order of the bodies in which neighbours are near in index: thin layers in z (a quarter
// diameter), bottom up, and within a layer a Morton (Z-order) curve over cells of one diameter
// in x and y: much the order a pour leaves (protocol/pour.cpp places grains layer by layer), which
// the threaded force loop relies on for its two-colour schedule (contact/verlet_contacts.cpp:
// a block's partners must not reach past the next block); a bed in another order (imported
// from elsewhere) takes private force arrays and a reduction instead. Intruders stay last, in
// their order.
#include <cstddef>
#include <vector>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace granudrag {

// order[k]: the index in p of the body that goes to position k.
std::vector<std::size_t> spatial_order(const Particles& p, const Box& box);
// p's bodies in that order (every array, forces included).
Particles reordered(const Particles& p, const std::vector<std::size_t>& order);

}  // namespace granudrag
