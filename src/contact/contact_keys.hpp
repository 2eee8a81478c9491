#pragma once
// The contact law's keys (kn, kt, gamman, gammat, mu, youngs_modulus, poisson_ratio, dt), bound
// to ContactParams's fields where they are one (core/parameter_table.hpp).
#include <string>
#include <utility>
#include <vector>

#include "contact/contact_params.hpp"
#include "core/parameter_table.hpp"

namespace granudrag {

const KeyTable<ContactParams>& contact_keys();

// Each contact key bound to one of c's fields, with that field's value, in the table's order:
// what a bed file stores, `info` prints and describe() writes, so a new key reaches all three.
std::vector<std::pair<std::string, double>> contact_fields(const ContactParams& c);

}  // namespace granudrag
