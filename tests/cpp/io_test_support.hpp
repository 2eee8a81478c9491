#pragma once
// What the io tests share: a temporary directory removed afterwards, reading a text file or
// bytes, checking that an error names what it should, and one small pulled bed to write files of.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "protocol/pull.hpp"

namespace granudrag::support {

namespace fs = std::filesystem;

// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("granudrag-io-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// 0.5 i - 3.25e-3: values that are neither integers nor exact in binary.
inline std::vector<double> ramp(std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = 0.5 * static_cast<double>(i) - 3.25e-3;
  return v;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// One small bed (60 soft grains, settled briefly) and a short pull on it, whose bed, run and
// checkpoint files the readers' tests write and damage.
struct PulledBed {
  Bed bed;
  std::unique_ptr<Pull> pull;
};
inline const PulledBed& pulled_bed() {
  static const PulledBed fx = [] {
    PulledBed f;
    PourSpec s;
    s.lx = 4;
    s.ly = 4;
    s.grains = 60;
    s.intruder_diameter = 1.2;
    s.intruder_x = 2;
    s.intruder_y = 2;
    s.depth = 1;
    s.contact = ContactParams{}.with_stiffness(2e4);
    s.ke_threshold = 1e-2;
    s.max_settle_time = 0.3;
    s.check_interval = 0.15;
    f.bed = pour(s, false);
    PullSpec p;
    p.distance = 0.05;
    p.snapshots = 1;
    f.pull = std::make_unique<Pull>(f.bed, p);
    f.pull->run(false);
    return f;
  }();
  return fx;
}

// Runs `body` and returns the granudrag::Error message it throws; fails the test otherwise.
template <class F>
std::string error_of(F&& body) {
  try {
    body();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-granudrag exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "did not throw";
  return {};
}

}  // namespace granudrag::support

#define EXPECT_MENTIONS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "message: " << (message)
