#pragma once
// What a file or `granudrag --version` says the engine is: the release (GRANUDRAG_VERSION, from
// CMakeLists.txt's project version) and the commit it was built from, "-dirty" when tracked
// files differed from it, "unknown" outside git. The commit is taken at each build
// (cmake/build_stamp.cmake), not when CMake configured the build tree.
namespace granudrag {

const char* build_commit();

}  // namespace granudrag
