// The keys of the contact law (paper Eqs. 1-3), declared once and bound to ContactParams's
// fields: every command that builds a contact law reads them (app/command.cpp, contact_from),
// prints them in --help and --schema, and ContactParams::validate() checks a ContactParams
// against their ranges; the bed file carries each field to the pull (io/bed_file.cpp), `granudrag
// info` prints each. The workflow's schema and config/README follow --schema
// (tools/schema_blocks.py); the analysis's ranges, for the keys its table has a column of, are
// checked against it (analysis/core/physics.py, CONTACT_RANGES). Adding a key: docs/engine.md.
// The time step's row (time_step_key) is here too, beside the collision time it defaults to,
// but no contact key: pour binds it to PourSpec::dt (pour_keys.cpp), the other commands that list
// it after the contact keys read it themselves.
#include "contact/contact_keys.hpp"

namespace granudrag {

// K_n, K_t and the dampings have no row default: K_n given or not decides how the other three
// follow (contact_from), so each help states the paper's value or ratio instead.
const KeyTable<ContactParams>& contact_keys() {
  static const KeyTable<ContactParams> keys = [] {
    const ContactParams paper;
    const std::string kn = number_text(paper.kn);
    return KeyTable<ContactParams>{
        Key::number("kn")
            .unit("rho d g")
            .above(0)
            .help("normal stiffness K_n (default " + kn +
                  ", the paper's); K_t, gamma_n, gamma_t default to the paper's ratios (K_t/K_n, "
                  "gamma_t/gamma_n and gamma_n/K_n^0.6 fixed)")
            .field(&ContactParams::kn)
            .read_by_command(),
        Key::number("kt")
            .unit("rho d g")
            .above(0)
            .help("tangential stiffness K_t (default " + number_text(paper.kt / paper.kn) + " K_n)")
            .field(&ContactParams::kt)
            .read_by_command(),
        Key::number("gamman")
            .unit("sqrt(g/d^3)")
            .at_least(0)
            .help("normal damping gamma_n (default " + number_text(paper.gamman) + " (K_n/" + kn + ")^0.6)")
            .field(&ContactParams::gamman)
            .read_by_command(),
        Key::number("gammat")
            .unit("sqrt(g/d^3)")
            .at_least(0)
            .help("tangential damping gamma_t (default gamma_n)")
            .field(&ContactParams::gammat)
            .read_by_command(),
        Key::number("mu").at_least(0).help("friction coefficient").field(&ContactParams::mu),
        Key::number("youngs_modulus")
            .unit("rho d g")
            .above(0)
            .help("instead of kn and kt: Young's modulus E (paper Eq. 3)"),
        Key::number("poisson_ratio")
            .default_value("0.3")
            .above(-1)
            .below(0.5)
            .help("Poisson ratio nu with youngs_modulus"),
    };
  }();
  return keys;
}

ParameterSpec time_step_key() {
  return Key::number("dt")
      .unit("sqrt(d/g)")
      .above(0)
      .help("time step (default: Hertz collision time of two 0.9 d grains at " +
            number_text(TimeStepPolicy::reference_speed) + " sqrt(gd), over " +
            number_text(TimeStepPolicy::steps_per_collision_default) + ")");
}

std::vector<std::pair<std::string, double>> contact_fields(const ContactParams& c) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& row : contact_keys().rows())
    if (row.number)
      if (const auto value = row.number(c)) out.emplace_back(row.spec.key, *value);
  return out;
}

}  // namespace granudrag
