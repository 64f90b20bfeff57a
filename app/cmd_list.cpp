// `apiclab list`: the shipped scenes and sweeps with the first sentence of their description.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "cli.hpp"
#include "commands.hpp"
#include "sim/scene/input_file.hpp"
#include "sim/scene/scene_json.hpp"

namespace apiclab::cli {

std::string first_sentence(const std::string& text) {
  for (std::size_t i = text.find(". "); i != std::string::npos; i = text.find(". ", i + 1))
    if (i + 2 < text.size() && std::isupper(static_cast<unsigned char>(text[i + 2])))
      return text.substr(0, i + 1);
  return text;
}

std::vector<std::filesystem::path> json_files(const std::string& dir) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

namespace {

// "  NAME  TEXT" with TEXT wrapped at word boundaries to lines of at most 100 characters, the
// continuation lines indented under its start.
void print_entry(const std::string& name, std::size_t width, const std::string& text) {
  constexpr std::size_t kLine = 100;
  const std::size_t indent = width + 4, room = kLine > indent + 20 ? kLine - indent : 20;
  std::printf("  %-*s  ", int(width), name.c_str());
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.size();
    if (end - start > room) {
      const std::size_t space = text.rfind(' ', start + room);
      end = space != std::string::npos && space > start ? space : start + room;
    }
    if (start > 0) std::printf("%*s", int(indent), "");
    std::printf("%s\n", text.substr(start, end - start).c_str());
    start = end < text.size() && text[end] == ' ' ? end + 1 : end;
  }
  if (text.empty()) std::printf("\n");
}

int list_scenes() {
  namespace fs = std::filesystem;
  const std::string dir = scenes_directory();
  const std::vector<fs::path> files = json_files(dir);
  if (files.empty()) throw UsageError("no shipped scenes found in '" + dir + "'");
  const std::string sweep_dir = (fs::path(assets_directory()) / "sweeps").string();
  const std::vector<fs::path> sweeps = json_files(sweep_dir);
  std::size_t width = 0;
  for (const auto& f : files) width = std::max(width, f.stem().string().size());
  for (const auto& f : sweeps) width = std::max(width, f.stem().string().size());
  std::printf("Shipped scenes (%s); run one with: apiclab run NAME\n", dir.c_str());
  for (const auto& f : files) {
    std::string line;
    try {
      const SceneDesc s = load_scene(f.string());
      line = std::to_string(s.dim) + "D  " +
             (s.description.empty() ? "(no description)" : first_sentence(s.description));
    } catch (const SceneError& e) {
      line = std::string("(does not load: ") + e.what() + ")";
    }
    print_entry(f.stem().string(), width, line);
  }
  if (sweeps.empty()) return 0;
  std::printf("Shipped sweeps (%s); run one with: apiclab sweep FILE --out DIR\n",
              sweep_dir.c_str());
  for (const auto& f : sweeps) {
    // Only the description is read here; `apiclab sweep` checks the rest of the spec.
    nlohmann::json spec;
    JsonError error;
    std::string line = "(no description)";
    try {
      if (!parse_json_strict(read_input_file(f.string(), "sweep file"), spec, error))
        line = "(does not parse: " + error.text() + ")";
      else if (spec.is_object() && spec.contains("description") && spec["description"].is_string())
        line = first_sentence(spec["description"].get<std::string>());
    } catch (const SceneError& e) {
      line = std::string("(cannot read: ") + e.what() + ")";
    }
    print_entry(f.stem().string(), width, line);
  }
  return 0;
}

}  // namespace

void register_list(CLI::App& root, CommandTable& table) {
  CLI::App* cmd =
      root.add_subcommand("list", "the shipped scenes and sweeps, each with its first sentence");
  table.push_back({cmd, [] { return list_scenes(); }});
}

}  // namespace apiclab::cli
