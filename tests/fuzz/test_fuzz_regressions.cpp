// Replays every input the fuzzers found (tests/fuzz_regressions/<target>/) and the seed corpora
// (tests/fuzz/corpus/<target>/) through the fuzz targets, so the default tests cover the findings
// without clang: each input must build or fail with one clean SceneError line.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "tests/fuzz/fuzz_targets.hpp"

namespace fs = std::filesystem;
using namespace apiclab::fuzz;

namespace {

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs each file under `dirs` (a missing one holds nothing); returns how many ran.
int replay(const std::string& target, const std::vector<fs::path>& dirs) {
  const Target run = target_named(target);
  EXPECT_NE(run, nullptr);
  int n = 0;
  for (const auto& dir : dirs) {
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (!e.is_regular_file() || e.path().extension() == ".md") continue;
      const std::string bytes = read_bytes(e.path());
      ++n;
      try {
        const Outcome o = run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
        EXPECT_FALSE(o.empty()) << e.path();
        if (std::getenv("APICLAB_FUZZ_VERBOSE"))
          std::printf("%s: %s\n", e.path().c_str(), o.c_str());
      } catch (const std::exception& ex) {
        ADD_FAILURE() << e.path() << ": " << ex.what();
      }
    }
  }
  return n;
}

const fs::path kRoot = fs::path(APICLAB_SOURCE_DIR);
const fs::path kFound = kRoot / "tests" / "fuzz_regressions";

}  // namespace

// Seeds first (the shipped scenes and meshes must pass too), then the findings.
TEST(FuzzRegressions, SceneInputs) {
  EXPECT_GT(replay("scene", {kRoot / "assets" / "scenes", kFound / "scene"}), 15);
}
TEST(FuzzRegressions, SetInputs) {
  EXPECT_GT(replay("set", {kRoot / "tests" / "fuzz" / "corpus" / "set", kFound / "set"}), 0);
}
TEST(FuzzRegressions, ObjInputs) {
  EXPECT_GT(replay("obj", {kRoot / "assets" / "meshes", kFound / "obj"}), 0);
}
