// `apiclab docs PAGE`: the Markdown that tools/gen-docs.sh splices into README.md and docs/,
// printed from the registries themselves so the pages cannot drift from the code.
#include <cstdio>
#include <string>

#include "app/assets.hpp"
#include "app/cli_checks.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/mpm/schemes/scheme_facts.hpp"
#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/layout_parameters.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab::cli {
namespace {

// A table cell: '|' would end the cell, a newline the row.
std::string cell(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

// The registry's method list ("eol eulerian") as the table prints it ("eol, eulerian").
std::string solver_family(std::string_view method) {
  if (method.empty()) return "all";
  std::string out;
  for (const char c : method) out += c == ' ' ? std::string(", ") : std::string(1, c);
  return out;
}

std::string unit_text(const NumericParameter& p) {
  if (p.unit_3d.empty()) return std::string(p.unit);
  return std::string(p.unit) + " (2D), " + std::string(p.unit_3d) + " (3D)";
}

void print_numeric_keys() {
  std::printf("| key | meaning | unit | allowed | default | solver |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  for (const NumericParameter& p : numeric_parameters())
    std::printf("| `%s` | %s | %s | %s%s | %s | %s |\n", std::string(p.key).c_str(),
                cell(p.help).c_str(), cell(unit_text(p)).c_str(), p.range.text().c_str(),
                p.integer ? ", integer" : "", cell(p.default_text()).c_str(),
                solver_family(p.method).c_str());
}

void print_choice_keys() {
  std::printf("| key | chooses | values | default | solver |\n");
  std::printf("| --- | --- | --- | --- | --- |\n");
  for (const ChoiceParameter& c : choice_parameters()) {
    std::string values;
    for (const ChoiceOption& o : c.options)
      values += (values.empty() ? "" : "<br>") + ("`" + o.key + "`: " + cell(o.help));
    std::printf("| `%s` | %s | %s | %s | %s |\n", std::string(c.key).c_str(), cell(c.what).c_str(),
                values.c_str(),
                c.default_key.empty() ? "required" : ("`" + c.default_key + "`").c_str(),
                solver_family(c.method).c_str());
  }
}

// The shape or sampling types that read a layout key, and whether 3D scenes alone do.
std::string read_by(const LayoutParameter& l) {
  std::string out = l.types.empty() ? "all" : solver_family(l.types);
  return l.only_3d ? out + " (3D)" : out;
}

void print_layout_keys() {
  std::printf("| key | meaning | value | unit | allowed | default | type |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- |\n");
  for (const LayoutParameter& l : layout_parameters())
    std::printf("| `%s` | %s | %s | %s | %s | %s | %s |\n", std::string(l.key).c_str(),
                cell(l.help).c_str(), l.form_text().c_str(), std::string(l.unit).c_str(),
                l.allowed_text().c_str(), cell(l.default_text()).c_str(), read_by(l).c_str());
}

int print_scene_keys() {
  std::printf(
      "Numbers (`sim/scene/parameters.cpp`; `*` stands for an index: `materials.0.E`, "
      "`gravity.1`):\n\n");
  print_numeric_keys();
  std::printf("\nWords and switches (`sim/scene/choice_parameters.cpp`):\n\n");
  print_choice_keys();
  std::printf(
      "\nLayout: the dimension, shapes, sampling, motion and colliders "
      "(`sim/scene/layout_parameters.cpp`; `*` stands for an object's or collider's index; "
      "type: the shape's or sampling's `type` that reads the key):\n\n");
  print_layout_keys();
  return 0;
}

int print_schemes() {
  std::printf("| `--scheme` | scheme | source | conserves |\n");
  std::printf("| --- | --- | --- | --- |\n");
  for (const auto& c : scheme_choices()) {
    const SchemeFacts f = scheme_facts(c.value);
    std::printf("| `%s` | %s | %s | %s |\n", std::string(c.key).c_str(),
                std::string(f.name).c_str(), cell(f.source).c_str(), cell(f.conserves).c_str());
  }
  return 0;
}

// The shipped scenes as their files describe themselves (relative to the repository root, as
// README.md links them).
int print_scenes() {
  std::printf("| scene | dim | solver | what it is |\n| --- | --- | --- | --- |\n");
  for (const auto& file : json_files(scenes_directory())) {
    const SceneDesc s = load_scene(file.string());
    const std::string solver = s.solver.method == "mpm"
                                   ? "mpm, " + std::string(key_of(s.solver.scheme)) + ", " +
                                         std::string(key_of(s.solver.integrator))
                                   : s.solver.method;
    std::printf("| [`%s`](assets/scenes/%s) | %dD | %s | %s |\n", file.stem().c_str(),
                file.filename().c_str(), s.dim, solver.c_str(),
                cell(first_sentence(s.description)).c_str());
  }
  return 0;
}

}  // namespace

void register_docs(CLI::App& root, CommandTable& table) {
  CLI::App* cmd = root.add_subcommand(
      "docs", "print a generated section of the manual (tools/gen-docs.sh splices it in)");
  static std::string page;
  cmd->add_option("page", page,
                  "scene-keys: every scene key from the registries; schemes: the transfer "
                  "schemes; scenes: the shipped scenes")
      ->required()
      ->check(one_of({"scene-keys", "schemes", "scenes"}));
  table.push_back({cmd, [] {
                     if (page == "schemes") return print_schemes();
                     if (page == "scenes") return print_scenes();
                     return print_scene_keys();
                   }});
}

}  // namespace apiclab::cli
