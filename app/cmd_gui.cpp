// `apiclab gui [SCENE] [--schemes a,b,c] [--screenshot FILE --frames N]`: the viewer.
// Compiled only with the GUI (app/app_extra.cmake defines APICLAB_HAVE_GUI).
#ifdef APICLAB_HAVE_GUI
#include <cstdio>
#include <sstream>

#include "cli.hpp"
#include "commands.hpp"
#include "gui/viewer.hpp"
#include "render/color.hpp"

namespace apiclab::cli {
namespace {

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

void register_gui(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<gui::ViewerOptions>();
  auto schemes = std::make_shared<std::string>();
  auto size = std::make_shared<std::string>();
  auto fast = std::make_shared<bool>(false);
  auto threads = std::make_shared<int>(0);
  CLI::App* cmd = root.add_subcommand(
      "gui", "Interactive viewer: live scheme switching, vectors, plots, side-by-side panes");
  cmd->add_option("scene", o->scene, "Scene file or shipped scene name (default rotating-disk)");
  cmd->add_option("--schemes", *schemes,
                  "One pane per scheme, side by side, e.g. pic,flip,apic (1-4)");
  cmd->add_option("--set", o->overrides, "Override a scene value by JSON path, KEY=VALUE");
  cmd->add_option("--precision", o->precision, "double|float");
  cmd->add_option("--color", o->color, choice_keys(color_mode_choices()) + " [default: speed]");
  cmd->add_flag("--vectors", o->vectors, "Show velocity vectors");
  cmd->add_flag("--fast", *fast, "Run as fast as possible instead of real time");
  cmd->add_flag("--paused", o->paused, "Start paused");
  cmd->add_option("--size", *size, "Window size WxH (default 1600x900)");
  cmd->add_option("--screenshot", o->screenshot,
                  "Save the window as PNG after --frames frames and exit");
  cmd->add_option("--frames", o->frames,
                  "Frames before the screenshot (each one simulated frame); alone: run live N "
                  "frames, print fps, exit");
  cmd->add_option("--threads", *threads, "Solver threads (OpenMP)");
  table.push_back({cmd, [o, schemes, size, fast, threads] {
                     o->realtime = !*fast;
                     o->schemes = split_commas(*schemes);
                     if (o->schemes.size() > 4) throw UsageError("--schemes: at most 4 panes");
                     for (auto& s : o->schemes) parse_choice(scheme_choices(), s, "scheme");
                     parse_choice(precision_choices(), o->precision, "precision");
                     render::parse_color_mode(o->color);
                     if (!size->empty() &&
                         std::sscanf(size->c_str(), "%dx%d", &o->width, &o->height) != 2)
                       throw UsageError("--size: expected WxH, e.g. 1600x900");
                     if (!o->screenshot.empty()) ensure_writable_file(o->screenshot);
                     if (!o->screenshot.empty() && o->frames <= 0) o->frames = 60;
                     apply_threads(*threads);
                     return gui::run_viewer(*o);
                   }});
}

bool gui_available() { return gui::display_available(); }

int run_default_gui() {
  gui::ViewerOptions o;
  o.schemes = {"pic", "flip", "apic"};
  o.vectors = true;
  return gui::run_viewer(o);
}

}  // namespace apiclab::cli

#endif  // APICLAB_HAVE_GUI
