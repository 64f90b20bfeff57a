// apiclab: research viewer for hybrid particle/grid simulation. Subcommand dispatch.
#include <cstdio>
#include <iostream>
#include <string>

#include "app/output_file.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/scene.hpp"

namespace {

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace apiclab::cli;
  CLI::App root{"apiclab: MPM with PIC, FLIP, APIC and RPIC transfers (Jiang et al. 2017)"};
  root.require_subcommand(0, 1);
  root.set_version_flag("--version", version_text());
  CommandTable table;
  register_run(root, table);
  register_roundtrip(root, table);
  register_bench(root, table);
  register_list(root, table);
  register_docs(root, table);
  register_sweep(root, table);
#ifdef APICLAB_HAVE_RENDER
  register_render(root, table);
#endif
#ifdef APICLAB_HAVE_GUI
  register_gui(root, table);
#endif
#ifdef APICLAB_HAVE_FIGURES
  register_figures(root, table);
#endif
  try {
    root.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return root.exit(e);
  } catch (const CLI::ParseError& e) {
    // Documented exit code 2 and one line, whatever CLI11's own code (104-109).
    std::string help = "apiclab --help";
    for (const CLI::App* sub : root.get_subcommands())
      help = "apiclab " + sub->get_name() + " --help";
    std::fprintf(stderr, "apiclab: %s (see %s)\n", one_line(e.what()).c_str(), help.c_str());
    return 2;
  }
  try {
    for (auto& c : table)
      if (c.app->parsed()) return c.action();
#ifdef APICLAB_HAVE_GUI
    if (gui_available()) return run_default_gui();
#endif
    std::cout << root.help();
    return 0;
  } catch (const apiclab::SceneError& e) {
    std::fprintf(stderr, "apiclab: %s\n", e.what());
  } catch (const UsageError& e) {
    std::fprintf(stderr, "apiclab: %s\n", e.what());
  } catch (const apiclab::WriteError& e) {
    // A full disk or a file size limit: "cannot write FILE: REASON" (docs/outputs.md).
    std::fprintf(stderr, "apiclab: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "apiclab: error: %s\n", e.what());
  }
  return 2;
}
