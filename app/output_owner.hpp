// Whose files an output path holds (docs/outputs.md, "Whose files"): a command replaces only
// the outputs that the same scene and settings wrote before, known by their settings sidecar
// (NAME.csv.json beside a CSV, frames.csv.json in a frame folder, the settings inside a run
// summary). Before anything runs it refuses, with one line naming the owner: an output that is
// one of the run's inputs, two outputs on one path, an existing file without an apiclab owner,
// and another run's outputs; --overwrite replaces the last two. Then it removes its own stale
// outputs (an earlier summary, the frames an earlier run left in a frame folder).
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"

namespace apiclab::cli {

// A scene's name as a file name that stays in its folder: letters, digits, '-', '_' and '.'
// kept, every other character '-', no leading '.', at most 100 characters, "scene" when empty.
std::string safe_file_name(const std::string& name);

// Whether `name` is a frame file apiclab writes (frame_0007.csv, frame_0007_grid0.vti,
// frame_0007_surface1.obj, frame_0007.png, or one of them with .part); its frame number in
// `frame` when it is.
bool is_frame_file_name(const std::string& name, long* frame = nullptr);

// "" when `theirs` are the same settings as `ours` (run_settings, app/run_outputs.hpp), else the
// first key that differs: "materials.0.E is 1000 there, 2000 here", "time.end is 0.5 there, 1
// here". The numeric parameters go by their own keys; `overrides` is left out (`--scheme flip`
// and `--set solver.scheme=flip` are the same settings), and so is the solver's label, which
// only spells the scheme and its parameter again; two spellings of one scene file are one.
// Outputs' owners and checkpoints are compared by it.
std::string settings_difference(const nlohmann::json& theirs, const nlohmann::json& ours);

class OutputClaims {
 public:
  // `owner`: the settings this command records in its sidecars (run_settings; compare adds its
  // panes); compared without `overrides`, which spell the same settings in more than one way.
  OutputClaims(nlohmann::json owner, bool overwrite);

  // Files the command reads: the scene file and its mesh files.
  void scene_inputs(const SceneDesc& scene);
  void input(const std::string& path, const std::string& what);

  // A diagnostics CSV and its sidecar PATH.json. `option` names it in messages ("--csv"); the
  // settings it records are `owner` (compare's panes), else the constructor's.
  void csv(const std::string& option, const std::string& path,
           const nlohmann::json& owner = nullptr);
  // A JSON file that holds its own settings (run --summary).
  void summary(const std::string& option, const std::string& path);
  // A frame folder: frame files, frames.csv with its sidecar frames.csv.json, series.pvd.
  void frames(const std::string& option, const std::string& dir,
              const nlohmann::json& owner = nullptr);
  // A file without a sidecar (gui --screenshot, render --video): replaced when its first bytes
  // at `offset` are `magic` (a PNG, an MP4), so only what apiclab writes is.
  void plain(const std::string& option, const std::string& path, const std::string& magic,
             std::size_t offset = 0);

  // Refuses what is not this command's (UsageError, one line), then removes its stale outputs.
  void check_and_clear() const;

 private:
  enum class Kind { csv, sidecar, summary, frames, plain };
  struct Claim {
    Kind kind;
    std::string option, path, magic;
    std::size_t offset = 0;
    nlohmann::json owner;  // the settings its sidecar records
  };
  struct Input {
    std::string path, what;
  };
  void check_inputs_and_paths() const;
  // Whether the claim's existing outputs are someone else's: throws unless --overwrite.
  void check_owner(const Claim& c) const;
  void clear(const Claim& c) const;

  nlohmann::json owner_;
  bool overwrite_;
  std::vector<Claim> claims_;
  std::vector<Input> inputs_;
};

}  // namespace apiclab::cli
