// apiclab: research viewer for hybrid particle/grid simulation. Subcommand dispatch.
#include <cstdio>
#include <iostream>

#include "cli.hpp"
#include "commands.hpp"
#include "sim/scene.hpp"

int main(int argc, char** argv) {
  using namespace apiclab::cli;
  CLI::App root{"apiclab: MPM with PIC, FLIP, APIC and RPIC transfers (Jiang et al. 2017)"};
  root.require_subcommand(0, 1);
  CommandTable table;
  register_run(root, table);
  register_roundtrip(root, table);
  register_bench(root, table);
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
  } catch (const CLI::ParseError& e) {
    return root.exit(e);
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
  } catch (const std::exception& e) {
    std::fprintf(stderr, "apiclab: error: %s\n", e.what());
  }
  return 2;
}
