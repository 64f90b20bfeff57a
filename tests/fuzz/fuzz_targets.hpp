// The fuzz targets (docs/testing.md, Fuzzing): each takes arbitrary bytes and either
// builds something or fails with one clean SceneError line. Anything else (another exception,
// a message over several lines or carrying a library's tag) is raised as FuzzFinding, so
// libFuzzer (tests/fuzz/fuzz_main.cpp) reports it as a crash and the replay test
// (tests/fuzz/test_fuzz_regressions.cpp) fails on it; crashes and hangs speak for themselves.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace apiclab::fuzz {

struct FuzzFinding : std::logic_error {
  using std::logic_error::logic_error;
};

// What a target did with an input: "ok" or the clean error line.
using Outcome = std::string;

// (a) scene JSON text -> validated scene -> solver built (memory capped) or one error.
Outcome scene_text(const std::uint8_t* data, std::size_t size);
// (b) the first byte picks a shipped scene; each line after the first is one `--set KEY=VALUE`.
Outcome set_overrides(const std::uint8_t* data, std::size_t size);
// (c) OBJ text -> closed mesh -> particles sampled inside it, or one error.
Outcome obj_mesh(const std::uint8_t* data, std::size_t size);

// The target by its name ("scene", "set", "obj"); null for another name.
using Target = Outcome (*)(const std::uint8_t*, std::size_t);
Target target_named(const std::string& name);

}  // namespace apiclab::fuzz
