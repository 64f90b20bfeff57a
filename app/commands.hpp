// Each subcommand registers its CLI11 subcommand and the action that runs it.
#pragma once
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "app/version.hpp"

namespace apiclab::cli {

struct Command {
  CLI::App* app;
  std::function<int()> action;
};
using CommandTable = std::vector<Command>;

void register_run(CLI::App& root, CommandTable& table);
void register_roundtrip(CLI::App& root, CommandTable& table);
void register_bench(CLI::App& root, CommandTable& table);
void register_list(CLI::App& root, CommandTable& table);
void register_docs(CLI::App& root, CommandTable& table);  // app/cmd_docs.cpp
// Up to the first ". " that ends a sentence (the next word starts with a capital letter).
std::string first_sentence(const std::string& text);                    // app/cmd_list.cpp
std::vector<std::filesystem::path> json_files(const std::string& dir);  // sorted *.json
void register_sweep(CLI::App& root, CommandTable& table);               // app/cmd_sweep.cpp
#ifdef APICLAB_HAVE_RENDER
void register_render(CLI::App& root, CommandTable& table);  // render and compare
#endif
#ifdef APICLAB_HAVE_GUI
void register_gui(CLI::App& root, CommandTable& table);
bool gui_available();   // a display can be opened
int run_default_gui();  // `apiclab` with no arguments and a display
#endif
#ifdef APICLAB_HAVE_FIGURES
void register_figures(CLI::App& root, CommandTable& table);
#endif

}  // namespace apiclab::cli
