// Parameters::apply_cli: `--key value` options and `--config FILE`.
#include <algorithm>
#include <optional>
#include <utility>

#include "core/error.hpp"
#include "core/parameters.hpp"

namespace granudrag {

using Type = ParameterSpec::Type;
using namespace detail;

void Parameters::apply_cli(const std::vector<std::string>& args) {
  const std::string see_help = " (granudrag " + command_ + " --help lists every option)";
  std::vector<std::string> configs;
  std::vector<std::pair<std::size_t, ParameterValue>> pending;
  std::vector<bool> given(specs_.size(), false);
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& arg = args[k];
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0)
      throw Error("unexpected argument '" + arg + "' for granudrag " + command_ +
                  ": options have the form --key value" + see_help);
    std::string name = arg.substr(2);
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    const bool next_is_value = k + 1 < args.size() && args[k + 1].compare(0, 2, "--") != 0;

    if (name == "config") {
      if (inline_value)
        configs.push_back(*inline_value);
      else if (next_is_value)
        configs.push_back(args[++k]);
      else
        throw Error("option '--config' needs the path of a YAML parameter file");
      continue;
    }
    const auto it =
        std::find_if(specs_.begin(), specs_.end(), [&](const ParameterSpec& s) { return s.key == name; });
    if (it == specs_.end())
      throw Error("unknown option '--" + name + "' for granudrag " + command_ +
                  suggestion(name, specs_, "--") + see_help);
    const std::size_t index = static_cast<std::size_t>(it - specs_.begin());
    if (given[index]) throw Error("option '--" + name + "' is given twice on the command line; keep one");
    given[index] = true;

    std::string text;
    if (inline_value)
      text = *inline_value;
    else if (next_is_value)  // a single '-' is a value: --mu -0.1
      text = args[++k];
    else if (it->type == Type::Flag)
      text = "true";
    else
      throw Error("option '--" + name + "' needs a value: " + expectation(it->type) +
                  (it->unit.empty() ? "" : " in " + it->unit) + see_help);
    pending.emplace_back(index, parse_value(*it, text, "--" + name + " on the command line", kCliLevel));
  }
  // Work on a copy: a bad file or value leaves *this untouched.
  Parameters staged = *this;
  for (const auto& path : configs) staged.load_yaml(path);
  for (auto& [index, value] : pending) staged.assign(index, std::move(value));
  *this = std::move(staged);
}

}  // namespace granudrag
