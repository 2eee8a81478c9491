#pragma once
// The subcommands of the granudrag executable. Each returns the process exit code and throws
// granudrag::Error for anything the user can fix.
#include <string>
#include <vector>

namespace granudrag {

int pour_command(const std::vector<std::string>& args);
int pull_command(const std::vector<std::string>& args);
int export_lammps_command(const std::vector<std::string>& args);
int import_lammps_command(const std::vector<std::string>& args);
int restitution_command(const std::vector<std::string>& args);

}  // namespace granudrag
