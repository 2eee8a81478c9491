#include "app/output_paths.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include <filesystem>

#include "core/error.hpp"
#include "io/file_header.hpp"

namespace granudrag {

namespace fs = std::filesystem;

namespace {

// The path with symbolic links and "." / ".." resolved, as far as it exists.
std::string resolved(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal().string() : p.string();
}

bool same_file(const std::string& a, const std::string& b) {
  if (resolved(a) == resolved(b)) return true;
  struct stat sa {
  }, sb{};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino;
}

// "--output b.h5" for an option, "the checkpoint b.h5.checkpoint.h5" for a file derived from one.
std::string option(const std::string& key, const std::string& path) {
  return (key.find(' ') == std::string::npos ? "--" + key : key) + " " + path;
}

std::string describe(const std::string& kind) {
  if (kind == "granudrag-bed") return "a bed file";
  if (kind == "granudrag-run") return "a run file";
  if (kind == "granudrag-checkpoint") return "a checkpoint";
  if (kind == "hdf5") return "an HDF5 file not written by granudrag";
  if (kind == "unreadable-hdf5") return "an HDF5 file that cannot be read";
  if (kind == "other") return "not an HDF5 file";
  if (kind == "text") return "a text file";
  if (kind.rfind("granudrag-", 0) == 0) return "a " + kind + " file";
  return kind;
}

bool is_hdf5_kind(const std::string& kind) { return kind.rfind("granudrag-", 0) == 0; }

void check_kind(const OutputFile& out) {
  const std::string found = file_kind(out.path);
  if (found == "missing" || found == "empty") return;
  const std::string where = option(out.key, out.path);
  if (found == "directory") throw Error(where + " is a directory: give a file name");
  bool same = false;
  if (is_hdf5_kind(out.kind))
    same = found == out.kind ||
           (out.replace_unreadable && (found == "unreadable-hdf5" || found == "other" || found == "hdf5"));
  else
    same = found == "other";  // a text output replaces a text file, never an HDF5 file
  if (!same)
    throw Error(where + " exists and is " + describe(found) + ", not " + describe(out.kind) +
                ": it is not replaced; choose another output path, or delete the file first");
}

}  // namespace

std::vector<InputFile> config_inputs(const std::vector<std::string>& args) {
  std::vector<InputFile> in;
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (args[k] == "--config" && k + 1 < args.size())
      in.push_back({"config", args[k + 1]});
    else if (args[k].rfind("--config=", 0) == 0)
      in.push_back({"config", args[k].substr(9)});
  }
  return in;
}

void check_outputs(const std::vector<InputFile>& inputs, const std::vector<OutputFile>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const OutputFile& out = outputs[i];
    for (const InputFile& in : inputs)
      if (same_file(out.path, in.path))
        throw Error(option(out.key, out.path) + " is the same file as " + option(in.key, in.path) +
                    ": choose another output path");
    for (std::size_t j = 0; j < i; ++j)
      if (same_file(out.path, outputs[j].path))
        throw Error(option(out.key, out.path) + " is the same file as " +
                    option(outputs[j].key, outputs[j].path) + ": choose another output path");
  }
  for (const OutputFile& out : outputs) check_kind(out);
  // A file its owner made read-only is kept, as cp and the shell keep it: the atomic write
  // (a rename over it) would otherwise replace it, since that needs only the directory.
  for (const OutputFile& out : outputs) {
    std::error_code ec;
    if (fs::is_regular_file(out.path, ec) && access(out.path.c_str(), W_OK) != 0 && errno == EACCES)
      throw Error(option(out.key, out.path) + " is read-only: make it writable (chmod u+w " + out.path +
                  ") to replace it, or choose another path");
  }
}

std::vector<OutputLock> claim_outputs(const std::vector<InputFile>& inputs,
                                      const std::vector<OutputFile>& outputs) {
  check_outputs(inputs, outputs);
  std::vector<OutputLock> locks;
  locks.reserve(outputs.size());
  for (const OutputFile& out : outputs)
    if (out.lock) locks.emplace_back(out.path);
  return locks;
}

}  // namespace granudrag
