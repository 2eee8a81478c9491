#pragma once
// The contact law's keys (kn, kt, gamman, gammat, mu, youngs_modulus, poisson_ratio, dt), bound
// to ContactParams's fields where they are one (core/parameter_table.hpp).
#include "contact/contact_params.hpp"
#include "core/parameter_table.hpp"

namespace granudrag {

const KeyTable<ContactParams>& contact_keys();

}  // namespace granudrag
