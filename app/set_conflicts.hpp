// Two assignments of one scene key that disagree: a command-line option and a `--set` of the
// key it sets (--scheme and --set solver.scheme=...), or the same key given twice by `--set`.
// Applied in order, the later one would win silently; they are refused instead, naming both
// (docs/cli.md). Assignments that agree are accepted.
#pragma once
#include <string>
#include <vector>

namespace apiclab::cli {

struct Assignment {
  std::string given;  // as the user wrote it: "--t-end 0.1", "--set time.end=5"
  std::string text;   // KEY=VALUE as applied to the scene
  // An option whose value is not known here (--frames sets time.end from the scene's fps):
  // any other assignment of its key disagrees with it.
  bool any_other_disagrees = false;
};

// Throws UsageError naming both assignments of the first pair, in the order given, that set
// one key (or a key and a section holding it) to different values. A value that is not JSON
// is compared as the string it stands for (a bare word); the scene parser judges it later.
void check_assignments(const std::vector<Assignment>& assignments);

}  // namespace apiclab::cli
