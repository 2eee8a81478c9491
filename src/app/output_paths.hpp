#pragma once
// Before a command does any work: its outputs must not be its inputs, nor each other, nor a
// file of another kind; then each output is locked against a second writer (io/output_lock).
#include <string>
#include <vector>

#include "io/output_lock.hpp"

namespace granudrag {

// A file a command reads: the option that names it ("bed", "config") and the path.
struct InputFile {
  std::string key;
  std::string path;
};

// A file a command writes. `kind`: what it is, as file_kind (io/file_header.hpp) says:
// "granudrag-bed", "granudrag-run", "granudrag-checkpoint" for HDF5 files, "text" for a text
// file (CSV, LAMMPS data or input, XDMF). An existing file at `path` is replaced only when it is
// of the same kind (or empty); `replace_unreadable` also lets an unreadable or foreign file be
// replaced (a checkpoint, which the command moves aside itself). `lock`: take its lock (derived
// files, such as <output>.xdmf, are covered by their main output's lock).
struct OutputFile {
  std::string key;  // "output", "output (checkpoint)", ...
  std::string path;
  std::string kind;
  bool lock = true;
  bool replace_unreadable = false;
};

// The --config files among a command's arguments, as inputs.
std::vector<InputFile> config_inputs(const std::vector<std::string>& args);

// Throws Error, naming both options and the fix, when an output is the same file as an input
// (same path after resolving symbolic links and "..", or the same device and inode: hard links)
// or as another output, or when an existing file of another kind is at an output's path.
void check_outputs(const std::vector<InputFile>& inputs, const std::vector<OutputFile>& outputs);

// check_outputs, then the locks of the outputs that take one, held until the result is
// destroyed (at the end of the command, also when it throws).
std::vector<OutputLock> claim_outputs(const std::vector<InputFile>& inputs,
                                      const std::vector<OutputFile>& outputs);

}  // namespace granudrag
