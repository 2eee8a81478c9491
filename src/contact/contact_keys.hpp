#pragma once
// The contact law's keys (kn, kt, gamman, gammat, mu, youngs_modulus, poisson_ratio), bound to
// ContactParams's fields where they are one (core/parameter_table.hpp), and the time step's (dt).
#include <string>
#include <utility>
#include <vector>

#include "contact/contact_params.hpp"
#include "core/parameter_table.hpp"

namespace granudrag {

const KeyTable<ContactParams>& contact_keys();

// The time step, dt: no default, meaning the Hertz collision time of two 0.9 d grains at the
// reference speed over steps_per_collision_default (not a contact law's field: pour binds it to
// PourSpec::dt, info, restitution, import-lammps and bench read it themselves).
ParameterSpec time_step_key();

// Each contact key bound to one of c's fields, with that field's value, in the table's order:
// what a bed file stores, `info` prints and describe() writes, so a new key reaches all three.
std::vector<std::pair<std::string, double>> contact_fields(const ContactParams& c);

}  // namespace granudrag
