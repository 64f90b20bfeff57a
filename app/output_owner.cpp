#include "app/output_owner.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>

#include "app/cli.hpp"
#include "sim/geometry/sampling.hpp"

namespace apiclab::cli {
namespace {

namespace fs = std::filesystem;

// An absolute, normal path with links resolved where they exist: two spellings of one file
// give one key.
std::string path_key(const std::string& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (!p.has_filename() && p.has_parent_path()) p = p.parent_path();  // "dir/" is "dir"
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(p, ec);
  return (ec ? p : resolved).string();
}

bool exists_here(const std::string& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

std::optional<nlohmann::json> read_json_object(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  return j;
}

// The settings recorded by a sidecar {"csv": NAME, "settings": {...}} that names `csv_name`.
std::optional<nlohmann::json> sidecar_settings(const std::string& sidecar,
                                               const std::string& csv_name) {
  const auto j = read_json_object(sidecar);
  if (!j || !j->contains("settings") || !(*j)["settings"].is_object() || !j->contains("csv") ||
      (*j)["csv"] != csv_name)
    return std::nullopt;
  return (*j)["settings"];
}

// The settings inside a run summary (it carries apiclab_version and settings).
std::optional<nlohmann::json> summary_settings(const std::string& path) {
  const auto j = read_json_object(path);
  if (!j || !j->contains("apiclab_version") || !j->contains("settings") ||
      !(*j)["settings"].is_object())
    return std::nullopt;
  return (*j)["settings"];
}

// Settings as flat KEY -> value text (the numeric parameters under their own keys), the
// `overrides` left out (`--scheme flip` and `--set solver.scheme=flip` are the same settings),
// and the label, which only spells the scheme and its parameter again.
void flatten(const nlohmann::json& j, const std::string& prefix,
             std::map<std::string, std::string>& out) {
  if (!j.is_object()) {
    out[prefix] = j.is_string() ? j.get<std::string>() : j.dump();
    return;
  }
  for (const auto& [key, value] : j.items()) {
    if ((prefix.empty() && key == "overrides") || (prefix == "solver" && key == "label")) continue;
    const std::string name = prefix.empty() || prefix == "parameters" ? key : prefix + "." + key;
    flatten(value, prefix.empty() && key == "parameters" ? "parameters" : name, out);
  }
}

bool same_file(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code ec;
  return fs::equivalent(a, b, ec) && !ec;
}

// A string field of a sidecar's settings, or "?" (the file may be anyone's).
std::string text_field(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "?";
}

// "rotating-disk, apic" (compare: its panes) for a message.
std::string owner_text(const nlohmann::json& settings) {
  const std::string scene = text_field(settings, "scene");
  if (settings.contains("panes") && settings["panes"].is_array()) {
    std::string panes;
    for (const auto& p : settings["panes"])
      panes += (panes.empty() ? "" : ",") + (p.is_string() ? p.get<std::string>() : p.dump());
    return scene + ", compare " + panes;
  }
  return scene + ", " + text_field(settings.value("solver", nlohmann::json()), "label");
}

std::string replace_hint(const char* what) {
  return std::string("; give another ") + what + ", or --overwrite to replace it";
}

// The frame numbers frames.csv lists (its first column, after the header).
std::vector<long> listed_frames(const std::string& frames_csv) {
  std::vector<long> frames;
  std::ifstream in(frames_csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) try {
      frames.push_back(std::stol(line.substr(0, line.find(','))));
    } catch (const std::exception&) {
    }
  return frames;
}

// The files of a frame folder besides the frames themselves.
const std::vector<std::string>& folder_index_files() {
  static const std::vector<std::string> names = {"frames.csv", "frames.csv.json", "series.pvd"};
  return names;
}

bool is_index_file_name(const std::string& name) {
  for (const std::string& n : folder_index_files())
    if (name == n || name == n + ".part") return true;
  return false;
}

void remove_file(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
  if (ec) throw UsageError("cannot remove " + p.string() + ": " + ec.message());
}

}  // namespace

std::string settings_difference(const nlohmann::json& theirs, const nlohmann::json& ours) {
  std::map<std::string, std::string> a, b;
  flatten(theirs, "", a);
  flatten(ours, "", b);
  std::set<std::string> keys;
  for (const auto& [k, v] : a) keys.insert(k);
  for (const auto& [k, v] : b) keys.insert(k);
  for (const std::string& k : keys) {
    const auto x = a.find(k), y = b.find(k);
    const std::string there = x == a.end() ? "unset" : x->second;
    const std::string here = y == b.end() ? "unset" : y->second;
    if (there == here || (k == "scene_file" && same_file(there, here))) continue;
    return k + " is " + there + " there, " + here + " here";
  }
  return "";
}

std::string safe_file_name(const std::string& name) {
  std::string s = name.substr(0, 100);
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.')
      ch = '-';
  for (char& ch : s) {  // a leading '.' would hide the file, or make ".." of it
    if (ch != '.') break;
    ch = '-';
  }
  return s.empty() ? "scene" : s;
}

bool is_frame_file_name(const std::string& name, long* frame) {
  static const std::regex pattern(
      R"(frame_([0-9]{4,9})(_grid[0-9]+|_surface[0-9]+)?\.(csv|vtp|vti|ply|obj|png)(\.part)?)");
  std::smatch m;
  if (!std::regex_match(name, m, pattern)) return false;
  if (frame) *frame = std::stol(m[1].str());
  return true;
}

OutputClaims::OutputClaims(nlohmann::json owner, bool overwrite)
    : owner_(std::move(owner)), overwrite_(overwrite) {}

void OutputClaims::scene_inputs(const SceneDesc& scene) {
  input(scene.source, "the scene file");
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].shape.type == ShapeType::mesh) try {
        input(resolve_mesh_file(scene, int(i)), "a mesh file");
      } catch (const std::exception&) {  // a missing mesh is the scene's own error
      }
}

void OutputClaims::input(const std::string& path, const std::string& what) {
  if (!path.empty()) inputs_.push_back({path, what});
}

void OutputClaims::csv(const std::string& option, const std::string& path,
                       const nlohmann::json& owner) {
  const nlohmann::json& settings = owner.is_null() ? owner_ : owner;
  claims_.push_back({Kind::csv, option, path, "", 0, settings});
  claims_.push_back({Kind::sidecar, "the settings sidecar of " + option + " " + path,
                     path + ".json", "", 0, settings});
}

void OutputClaims::summary(const std::string& option, const std::string& path) {
  claims_.push_back({Kind::summary, option, path, "", 0, owner_});
}

void OutputClaims::frames(const std::string& option, const std::string& dir,
                          const nlohmann::json& owner) {
  claims_.push_back({Kind::frames, option, dir, "", 0, owner.is_null() ? owner_ : owner});
}

void OutputClaims::plain(const std::string& option, const std::string& path,
                         const std::string& magic, std::size_t offset) {
  claims_.push_back({Kind::plain, option, path, magic, offset, owner_});
}

void OutputClaims::check_and_clear() const {
  check_inputs_and_paths();
  for (const Claim& c : claims_) check_owner(c);
  for (const Claim& c : claims_) clear(c);
}

void OutputClaims::check_inputs_and_paths() const {
  // Every file path the claims name, with how a message calls it.
  struct File {
    std::string key, path, text;
  };
  std::vector<File> files;
  std::vector<File> folders;
  for (const Claim& c : claims_) {
    const std::string text = c.kind == Kind::sidecar ? c.option : c.option + " " + c.path;
    if (c.kind != Kind::frames) {
      files.push_back({path_key(c.path), c.path, text});
      continue;
    }
    folders.push_back({path_key(c.path), c.path, text});
    for (const std::string& name : folder_index_files()) {
      const std::string p = (fs::path(c.path) / name).string();
      files.push_back({path_key(p), p, "the " + name + " of " + text});
    }
  }
  for (const File& f : files)
    for (const Input& in : inputs_)
      if (exists_here(f.path) && same_file(f.path, in.path))
        throw UsageError(f.text +
                         (f.text.find(f.path) == std::string::npos ? ", " + f.path + "," : "") +
                         " is " + in.what +
                         " this command reads: an output never replaces an input; give another "
                         "path");
  for (std::size_t i = 0; i < files.size(); ++i) {
    for (std::size_t j = i + 1; j < files.size(); ++j)
      if (files[i].key == files[j].key)
        throw UsageError(files[i].text + " and " + files[j].text +
                         " are one file; give each output its own path");
    for (const File& d : folders) {
      const fs::path key(files[i].key);
      if (files[i].key == d.key)
        throw UsageError(files[i].text + " and " + d.text + " are one path; give each its own");
      if (key.parent_path().string() == d.key && is_frame_file_name(key.filename().string()))
        throw UsageError(files[i].text + " is named as a frame file of " + d.text +
                         "; give each output its own path");
    }
  }
  for (std::size_t i = 0; i < folders.size(); ++i)
    for (std::size_t j = i + 1; j < folders.size(); ++j)
      if (folders[i].key == folders[j].key)
        throw UsageError(folders[i].text + " and " + folders[j].text +
                         " are one folder; give each its own");
}

void OutputClaims::check_owner(const Claim& c) const {
  const std::string named = c.option + " " + c.path;
  const auto refuse_other = [&](const nlohmann::json& theirs, const std::string& sidecar,
                                const char* what, const char* noun) {
    const std::string diff = settings_difference(theirs, c.owner);
    if (diff.empty() || overwrite_) return;
    throw UsageError(named + " holds another run's " + what + " (" + owner_text(theirs) + ": " +
                     diff + "; " + sidecar + ")" + replace_hint(noun));
  };
  switch (c.kind) {
    case Kind::csv: {
      std::error_code ec;  // a folder is refused by the writability check
      if (!exists_here(c.path) || fs::is_directory(c.path, ec) || overwrite_) return;
      const std::string sidecar = c.path + ".json";
      const auto theirs = sidecar_settings(sidecar, fs::path(c.path).filename().string());
      if (!theirs)
        throw UsageError(named + ": the file exists and no sidecar " + sidecar +
                         " names its owner (apiclab did not write it, or wrote it before "
                         "sidecars)" +
                         replace_hint("path"));
      return refuse_other(*theirs, sidecar, "diagnostics", "path");
    }
    case Kind::sidecar: {  // beside a CSV that is not there yet
      const std::string csv = c.path.substr(0, c.path.size() - 5);
      if (!exists_here(c.path) || exists_here(csv) || overwrite_) return;
      const auto theirs = sidecar_settings(c.path, fs::path(csv).filename().string());
      if (!theirs)
        throw UsageError(c.path + " exists and is not the settings sidecar apiclab writes for " +
                         csv + replace_hint("path"));
      return refuse_other(*theirs, c.path, "settings", "path");
    }
    case Kind::summary: {
      if (!exists_here(c.path) || overwrite_) return;
      const auto theirs = summary_settings(c.path);
      if (!theirs)
        throw UsageError(named + ": the file exists and is not an apiclab run summary" +
                         replace_hint("path"));
      return refuse_other(*theirs, c.path, "summary", "path");
    }
    case Kind::frames: {
      std::error_code ec;
      if (!fs::is_directory(c.path, ec) || overwrite_) return;
      const std::string sidecar = (fs::path(c.path) / "frames.csv.json").string();
      if (const auto theirs = sidecar_settings(sidecar, "frames.csv"))
        return refuse_other(*theirs, sidecar, "frames", "folder");
      for (const auto& e : fs::directory_iterator(c.path, ec)) {
        const std::string name = e.path().filename().string();
        if (is_frame_file_name(name) || is_index_file_name(name))
          throw UsageError(named + ": " + e.path().string() + " exists and no sidecar " + sidecar +
                           " names its owner (apiclab did not write it, or wrote it before "
                           "sidecars)" +
                           replace_hint("folder"));
      }
      return;
    }
    case Kind::plain: {
      if (!exists_here(c.path) || overwrite_) return;
      std::ifstream in(c.path, std::ios::binary);
      std::string head(c.offset + c.magic.size(), '\0');
      in.read(head.data(), std::streamsize(head.size()));
      if (!in || head.compare(c.offset, c.magic.size(), c.magic) != 0)
        throw UsageError(named + ": the file exists and is not the kind apiclab writes there" +
                         replace_hint("path"));
      return;
    }
  }
}

void OutputClaims::clear(const Claim& c) const {
  std::error_code ec;
  if (c.kind == Kind::summary && fs::is_regular_file(c.path, ec)) {
    remove_file(c.path);  // no earlier summary stands beside this run's outputs
    return;
  }
  if (c.kind != Kind::frames || !fs::is_directory(c.path, ec)) return;
  const fs::path dir(c.path);
  // An own folder: the frames its frames.csv lists, and the one after them (a run killed
  // between a frame's files and its row); any other folder (--overwrite): every frame file.
  const auto theirs = sidecar_settings((dir / "frames.csv.json").string(), "frames.csv");
  const bool own = theirs && settings_difference(*theirs, c.owner).empty();
  std::set<long> stale;
  if (own) {
    const std::vector<long> listed = listed_frames((dir / "frames.csv").string());
    stale.insert(listed.begin(), listed.end());
    stale.insert(listed.empty() ? 0 : *std::max_element(listed.begin(), listed.end()) + 1);
  }
  std::vector<fs::path> doomed;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    long frame = -1;
    const bool part = name.size() > 5 && name.compare(name.size() - 5, 5, ".part") == 0;
    if (is_index_file_name(name) ||
        (is_frame_file_name(name, &frame) && (!own || part || stale.count(frame))))
      doomed.push_back(e.path());
  }
  for (const fs::path& p : doomed) remove_file(p);
}

}  // namespace apiclab::cli
