// `apiclab gui [SCENE] [--schemes a,b,c] [--screenshot FILE --frames N]`: the viewer.
// Compiled only with the GUI (app/charts_and_viewer.cmake defines APICLAB_HAVE_GUI).
#ifdef APICLAB_HAVE_GUI
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "app/checkpoint.hpp"
#include "app/cli_checks.hpp"
#include "app/output_owner.hpp"
#include "app/pane_spec.hpp"
#include "app/sweep/open.hpp"
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

// The whole of "WxH", each side within what X servers and GL drivers take: GLFW asserts on a
// negative size, refuses 0 with two lines, and X aborts on a 100000-pixel side (gui soak).
void parse_window_size(const std::string& text, int& width, int& height) {
  constexpr int kMaxSide = 8192;
  int w = 0, h = 0, used = 0;
  if (std::sscanf(text.c_str(), "%dx%d%n", &w, &h, &used) != 2 || used != int(text.size()))
    throw UsageError("--size: expected WxH, e.g. 1600x900, got '" + text.substr(0, 40) + "'");
  if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide)
    throw UsageError("--size " + text + ": each side must be 1 to " + std::to_string(kMaxSide) +
                     " pixels");
  width = w, height = h;
}

// --screenshot FILE: not an input, and an existing FILE replaced only when it is a PNG (or with
// --overwrite); the PNG itself is written whole (render/image.hpp).
void claim_screenshot(const std::string& file, bool overwrite, const SceneDesc* scene) {
  OutputClaims claims(nullptr, overwrite);
  if (scene) claims.scene_inputs(*scene);
  claims.plain("--screenshot", file, "\x89PNG\r\n\x1a\n");
  claims.check_and_clear();
  ensure_writable_file(file);
}

}  // namespace

void register_gui(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<gui::ViewerOptions>();
  auto run = std::make_shared<RunOptions>();
  auto schemes = std::make_shared<std::string>();
  auto size = std::make_shared<std::string>();
  auto fast = std::make_shared<bool>(false);
  auto frames = std::make_shared<std::optional<int>>();
  auto sweep_dir = std::make_shared<std::string>();
  auto sweep_run = std::make_shared<std::string>();
  auto overwrite = std::make_shared<bool>(false);
  CLI::App* cmd = root.add_subcommand(
      "gui", "Interactive viewer: live scheme switching, vectors, plots, side-by-side panes");
  // The common options of run (scene, scheme, kernel, integrator, dt, t-end, flip-alpha, ...).
  add_run_options(cmd, *run,
                  {.scene_required = false, .frames = false, .outputs = false, .quiet = false});
  cmd->add_option("--schemes", *schemes,
                  "Panes side by side in lockstep from the same scene (1-4), as compare's: MPM "
                  "schemes (apic or mpm:apic) or methods without schemes (eol, eulerian), e.g. "
                  "apic,eol,eulerian [default: one pane, the scene's method and scheme]");
  cmd->add_option("--color", o->color, choice_keys(color_mode_choices()) + " [default: speed]");
  cmd->add_flag("--vectors", o->vectors, "Show velocity vectors [default: off]");
  cmd->add_flag("--fast", *fast, "Run as fast as possible instead of real time [default: off]");
  cmd->add_flag("--paused", o->paused, "Start paused [default: off]");
  cmd->add_option("--size", *size, "Window size WxH [default: 1600x900]");
  cmd->add_option("--screenshot", o->screenshot,
                  "Save the window as PNG after --frames frames and exit [default: none]");
  cmd->add_flag("--overwrite", *overwrite,
                "with --screenshot: replace FILE even when it is not a PNG [default: off]");
  cmd->add_option("--frames", *frames,
                  "Frames before the screenshot (each one simulated frame); alone: run live N "
                  "frames, print fps, exit [allowed: 1 or more; default: 60 with --screenshot, "
                  "else run until closed]");
  cmd->add_option("--sweep", *sweep_dir,
                  "Open a sweep folder (apiclab sweep --out DIR): its charts under the panes; "
                  "a click on a point or a stability cell runs that configuration beside its "
                  "reference [default: none]");
  cmd->add_option("--sweep-run", *sweep_run,
                  "With --sweep: start with this run (its id, runs.csv's first column) beside "
                  "its reference [default: the first scene's reference run alone]");
  cmd->add_option("--open-checkpoint", o->open_checkpoint,
                  "Open a run's checkpoint folder (run --checkpoint-every, or the viewer's Save) "
                  "as the pane, paused where the run stood [default: none]");
  cmd->add_option("--save-checkpoint", o->save_checkpoint,
                  "With --screenshot or --frames: at the end, save the pane as a run's "
                  "checkpoint into this folder (several panes: DIR/pane-1, ...); apiclab run "
                  "--resume DIR continues it [default: none]");
  cmd->add_option("--heartbeat", o->heartbeat,
                  "Rewrite FILE after every frame with 'FRAME SECONDS' (a watchdog's liveness "
                  "check, tests/gui/gui_soak.sh) [default: none]");
  table.push_back(
      {cmd, [o, run, schemes, size, fast, frames, sweep_dir, sweep_run, overwrite] {
         o->realtime = !*fast;
         o->schemes = split_commas(*schemes);
         if (o->schemes.size() > 4) throw UsageError("--schemes: at most 4 panes");
         if (!o->schemes.empty() && !run->scheme.empty())
           throw UsageError("--scheme and --schemes both pick the scheme; give one");
         std::vector<PaneSpec> panes;  // the same list as compare's (app/pane_spec.hpp)
         if (!schemes->empty()) try {
             panes = parse_panes(*schemes);
           } catch (const std::invalid_argument& e) {
             throw UsageError(e.what());
           }
         if (*frames && **frames < 1) throw UsageError("--frames must be at least 1");
         if (*frames) o->frames = **frames;
         if (!run->scene.empty()) o->scene = run->scene;
         o->overrides = option_overrides(*run);
         o->precision = run->precision;
         o->max_memory_gb = max_memory_gb(run->max_memory);
         try {
           render::parse_color_mode(o->color);
         } catch (const std::invalid_argument& e) {
           throw UsageError(e.what());
         }
         if (!size->empty()) parse_window_size(*size, o->width, o->height);
         if (!o->heartbeat.empty()) try {
             ensure_writable_file(o->heartbeat);
           } catch (const UsageError& e) {
             throw UsageError(std::string("--heartbeat: ") + e.what());
           }
         if (!o->screenshot.empty() && o->frames <= 0) o->frames = 60;
         if (!o->save_checkpoint.empty() && o->frames <= 0)
           throw UsageError(
               "--save-checkpoint DIR saves at the end of --screenshot or --frames N (in the "
               "window: the Save button under Run)");
         if (!o->open_checkpoint.empty()) {
           if (!run->scene.empty() || !schemes->empty() || !o->overrides.empty() ||
               !sweep_dir->empty())
             throw UsageError(
                 "--open-checkpoint DIR runs the checkpoint's own scene and options; give no "
                 "SCENE, --schemes, --sweep, --set or solver options");
           read_checkpoint(o->open_checkpoint);  // a bad folder: one line, exit 2
           if (!o->screenshot.empty()) claim_screenshot(o->screenshot, *overwrite, nullptr);
           apply_threads(run->threads);
           return gui::run_viewer(*o);
         }
         if (!sweep_run->empty() && sweep_dir->empty())
           throw UsageError("--sweep-run needs --sweep DIR");
         if (!sweep_dir->empty()) {
           // Each pane runs its configuration as the sweep's runner gave it to `run`.
           if (!run->scene.empty() || !schemes->empty() || !o->overrides.empty())
             throw UsageError(
                 "--sweep DIR runs its own configurations; give no SCENE, --schemes, --set or "
                 "solver options");
           if (!o->screenshot.empty()) claim_screenshot(o->screenshot, *overwrite, nullptr);
           o->sweep = sweep::open_sweep(*sweep_dir);  // a bad folder: one line, exit 2
           if (!sweep_run->empty()) o->sweep_run = long(sweep::run_with_id(*o->sweep, *sweep_run));
           const std::size_t first = o->sweep_run >= 0 ? std::size_t(o->sweep_run)
                                                       : o->sweep->plan.runs.front().reference;
           const sweep::SweepLaunch launch = sweep::launch_run(*o->sweep, first);  // checks them
           for (const auto& pane : launch.panes)  // each pane keeps its initial state
             check_memory_for(*pane.scene, *pane.precision, 2);
           apply_threads(run->threads);
           return gui::run_viewer(*o);
         }
         // The scene as the viewer will load it: bad input fails here with exit 2.
         RunOptions check = *run;
         check.scene = o->scene;
         SceneDesc scene = load_scene_with_options(check);
         if (!o->screenshot.empty()) claim_screenshot(o->screenshot, *overwrite, &scene);
         if (panes.empty()) panes.push_back({"", scene.solver.method, scene.solver.scheme});
         // As compare: a scheme that cannot run with this scene, up front.
         if (const std::string why = pane_conflict(panes, scene.solver); !why.empty())
           throw UsageError(why);
         // Each pane keeps its initial state for resets (app/sim_worker.cpp).
         check_memory_for(scene, precision_of(*run), 2 * int(panes.size()));
         if (run->flip_alpha && std::none_of(panes.begin(), panes.end(), [](const PaneSpec& p) {
               return p.method == "mpm" && blends_flip(p.scheme);
             }))
           std::fprintf(stderr,
                        "apiclab: warning: --flip-alpha only affects FLIP panes and "
                        "none is FLIP yet (a pane can switch to FLIP in the window)\n");
         apply_threads(run->threads);
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
