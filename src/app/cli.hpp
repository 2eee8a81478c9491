#pragma once
// Command-line options of the form --key value, checked against the keys a command accepts.
#include <map>
#include <string>
#include <vector>

namespace granudrag {

class Options {
 public:
  // Throws granudrag::Error for an unknown key or a key without a value.
  Options(const std::vector<std::string>& args, const std::vector<std::string>& allowed,
          const std::string& command);
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  std::string text(const std::string& key, const std::string& fallback) const;
  double number(const std::string& key, double fallback) const;
  long integer(const std::string& key, long fallback, long min_value) const;
  std::vector<int> integer_list(const std::string& key, const std::vector<int>& fallback) const;

 private:
  std::string command_;
  std::map<std::string, std::string> values_;
};

}  // namespace granudrag
