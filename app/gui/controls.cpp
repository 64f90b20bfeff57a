// The control column: scene, playback, panes and schemes (live), solver and material values
// (restart), view options, and throughput. Every combo is built from the registry's keys and
// every number field from the numeric-parameter registry (sim/scene/parameters.hpp), whose
// validation an edit passes before it reaches the solver.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "app/gui/pane_checkpoint.hpp"
#include "app/gui/view_limits.hpp"
#include "app/gui/viewer_state.hpp"
#include "render/color.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab::gui {
namespace {

const ImVec4 kError{0.80f, 0.12f, 0.12f, 1};
const ImVec4 kMuted{0.42f, 0.42f, 0.45f, 1};
const ImVec4 kNote{0.70f, 0.42f, 0.0f, 1};

// A combo over a registry list; the hovered choice shows its help line.
template <class E>
bool choice_combo(const char* label, E& value, const std::vector<Choice<E>>& choices) {
  bool changed = false;
  if (ImGui::BeginCombo(label, std::string(choice_key(choices, value)).c_str())) {
    for (auto& c : choices) {
      if (ImGui::Selectable(std::string(c.key).c_str(), c.value == value) && c.value != value)
        value = c.value, changed = true;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(c.help).c_str());
    }
    ImGui::EndCombo();
  }
  return changed;
}

// The same with a first entry meaning "the scene's value"; the closed combo names what it
// sets and the value in use: "kernel: quadratic".
template <class E>
bool optional_combo(const char* label, std::optional<E>& value,
                    const std::vector<Choice<E>>& choices, const std::string& what,
                    const std::string& scene_value) {
  bool changed = false;
  const std::string shown =
      what + ": " + (value ? std::string(choice_key(choices, *value)) : scene_value);
  // No arrow: the room goes to the text ("integrator: symplectic" in half the column).
  if (ImGui::BeginCombo(label, shown.c_str(), ImGuiComboFlags_NoArrowButton)) {
    if (ImGui::Selectable(("scene's: " + scene_value).c_str(), !value) && value)
      value.reset(), changed = true;
    for (auto& c : choices) {
      if (ImGui::Selectable(std::string(c.key).c_str(), value && *value == c.value) &&
          !(value && *value == c.value))
        value = c.value, changed = true;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(c.help).c_str());
    }
    ImGui::EndCombo();
  }
  return changed;
}

// The longest start of `text` (cut at a character boundary, with "..." when cut) that wraps at
// `width` into at most `lines` lines; measured, not drawn.
std::size_t fitting_length(const std::string& text, float width, int lines) {
  const float room = float(lines) * ImGui::GetTextLineHeight() + 0.5f;
  const auto height = [&](std::size_t n) {
    const std::string shown = text.substr(0, n) + (n < text.size() ? "..." : "");
    return ImGui::CalcTextSize(shown.c_str(), nullptr, false, width).y;
  };
  if (height(text.size()) <= room) return text.size();
  std::size_t lo = 0, hi = std::min<std::size_t>(text.size(), 4000);  // height(lo) fits
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (height(mid) <= room ? lo : hi) = mid;
  }
  while (lo > 0 && (static_cast<unsigned char>(text[lo]) & 0xC0) == 0x80) --lo;  // UTF-8
  return lo;
}

// The scene's description in a few wrapped lines, cut with "..." and whole (up to a few
// thousand characters) in a tooltip: a 25,000-character description drawn whole overflowed
// ImGui's 16-bit vertex indices (an assertion, exit 134) and pushed every control off the panel.
void description_text(ViewerState& st) {
  constexpr int kLines = 4;
  constexpr std::size_t kTooltipChars = 3000;
  const std::string& text = st.scene.description;
  const float width = ImGui::GetContentRegionAvail().x;
  const std::size_t n = fitting_length(text, width, kLines);
  const float top = ImGui::GetCursorPosY();
  ImGui::PushStyleColor(ImGuiCol_Text, kMuted);
  ImGui::PushTextWrapPos(0);
  const std::string shown = text.substr(0, n) + (n < text.size() ? "..." : "");
  ImGui::TextUnformatted(shown.c_str(), shown.c_str() + shown.size());
  ImGui::PopTextWrapPos();
  ImGui::PopStyleColor();
  st.description_shown = n;
  st.description_px = ImGui::GetCursorPosY() - top;
  if (n == text.size() || !ImGui::IsItemHovered()) return;
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(40 * ImGui::GetFontSize());
  std::size_t cut = std::min(text.size(), kTooltipChars);
  while (cut > 0 && cut < text.size() && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80)
    --cut;
  ImGui::TextUnformatted(text.c_str(), text.c_str() + cut);
  if (cut < text.size())
    ImGui::TextDisabled("... (%zu characters in all; the whole text is in the scene file)",
                        text.size());
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

// Where an item is drawn, for the layout tests (ViewerState::layout).
void record(ViewerState& st, const std::string& name, ImVec2 min, ImVec2 max) {
  st.layout[name] = ImVec4(min.x, min.y, max.x - min.x, max.y - min.y);
}

// The text a closed combo shows, from where the last item starts: the tests check it fits it.
void record_text(ViewerState& st, const std::string& name, const std::string& text) {
  const ImVec2 at = ImGui::GetItemRectMin();
  const float w = ImGui::CalcTextSize(text.c_str()).x + 2 * ImGui::GetStyle().FramePadding.x;
  record(st, name, at, ImVec2(at.x + w, ImGui::GetItemRectMax().y));
}

void section(const char* title) {
  ImGui::Spacing();
  ImGui::TextColored(ImVec4(0.15f, 0.30f, 0.55f, 1), "%s", title);
  ImGui::Separator();
}

void restart_because(ViewerState& st, SimWorker& worker, const std::string& what) {
  try {
    validate(st.scene);  // the reader's check: no invalid scene reaches a solver
  } catch (const SceneError& e) {
    st.load_error = e.what();
    return;
  }
  st.notice = what + " changed: restarted from t = 0";
  restart(st, worker);
}

// The number field being typed in. ImGui activates one item at a time; the typed value is
// applied when the field is left, not on every keystroke.
struct PendingEdit {
  ImGuiID id = 0;
  double value = 0;
};
PendingEdit& pending_edit() {
  static PendingEdit edit;
  return edit;
}

// A scene number from the registry: label and unit, the help and allowed range as tooltip, a
// slider over a bounded range. The new value goes through apply_parameter, the scene reader's
// validation: a value outside the range shows the reader's message and the old value stays.
void parameter_field(ViewerState& st, SimWorker& worker, const std::string& key) {
  int index = 0;
  const NumericParameter* p = find_parameter(key, &index);
  if (!p) return;
  const std::string label = std::string(p->label) + " [" + p->unit_for(st.scene.dim) + "]##" + key;
  const ImGuiID id = ImGui::GetID(label.c_str());
  PendingEdit& edit = pending_edit();
  double value = edit.id == id ? edit.value : p->get(st.scene, index);
  const Range& r = p->range;
  // A count (XPIC's m, PolyPIC's modes) is typed: a slider would give fractions, refused.
  const bool bounded = std::isfinite(r.lo) && std::isfinite(r.hi) && !p->integer;
  const bool changed =
      bounded
          ? ImGui::SliderScalar(label.c_str(), ImGuiDataType_Double, &value, &r.lo, &r.hi, "%.3g")
          : ImGui::InputDouble(label.c_str(), &value, 0, 0, p->integer ? "%.0f" : "%.4g");
  if (changed) edit = {id, value};
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s: %s", key.c_str(), p->describe().c_str());
  if (!ImGui::IsItemDeactivatedAfterEdit() || edit.id != id) return;
  edit.id = 0;
  if (edit.value == p->get(st.scene, index)) return;
  try {
    apply_parameter(st.scene, key, edit.value);
  } catch (const SceneError& e) {
    st.load_error = e.what();
    return;
  }
  st.load_error.clear();
  restart_because(st, worker, std::string(p->label));
}

std::string human(double v, const char* unit) {
  char buf[64];
  const char* prefix[] = {"", "k", "M", "G", "T"};
  int k = 0;
  while (v >= 1000 && k < 4) v /= 1000, ++k;
  std::snprintf(buf, sizeof buf, "%.3g %s%s", v, prefix[k], unit);
  return buf;
}

void scene_section(ViewerState& st, SimWorker& worker) {
  section("Scene");
  const std::string current = std::filesystem::path(st.scene_path).stem().string();
  ImGui::SetNextItemWidth(-1);
  if (ImGui::BeginCombo("##scene", current.c_str())) {
    for (auto& f : st.scene_files) {
      const std::string name = std::filesystem::path(f).stem().string();
      if (ImGui::Selectable(name.c_str(), f == st.scene_path)) load_scene_file(st, worker, f);
    }
    ImGui::EndCombo();
  }
  ImGui::SetNextItemWidth(-60);
  const bool enter =
      ImGui::InputTextWithHint("##open", "path/to/scene.json", st.open_path, sizeof st.open_path,
                               ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  if ((ImGui::Button("Open", ImVec2(-1, 0)) || enter) && st.open_path[0])
    load_scene_file(st, worker, st.open_path);
  if (!st.load_error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kError);
    ImGui::TextWrapped("%s", st.load_error.c_str());
    ImGui::PopStyleColor();
  }
  // A sweep folder: its charts under the panes (app/gui/sweep_panel.cpp).
  ImGui::SetNextItemWidth(-100);
  const bool sweep_enter =
      ImGui::InputTextWithHint("##sweep", "sweep folder (sweep --out DIR)", st.sweep_path,
                               sizeof st.sweep_path, ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  if ((ImGui::Button("Open sweep", ImVec2(-1, 0)) || sweep_enter) && st.sweep_path[0])
    open_sweep_folder(st, worker, st.sweep_path);
  if (!st.sweep_error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kError);
    ImGui::TextWrapped("%s", st.sweep_error.c_str());
    ImGui::PopStyleColor();
  }
  if (st.sweep && ImGui::SmallButton("close sweep")) {
    // The panes drop their runs' own scenes: they run the reference's scene with their schemes.
    st.sweep.reset(), st.sweep_run = -1;
    for (PaneConfig& c : st.panes) c.scene.reset(), c.precision.reset(), c.label.clear();
    st.notice = "sweep closed: the panes run the reference's scene, from t = 0";
    restart(st, worker);
  }
  if (st.scene_loaded && !st.scene.description.empty()) description_text(st);
}

// A folder for checkpoints: Save writes the panes as runs' checkpoints, Open reads one as a
// pane (app/gui/pane_checkpoint.hpp).
void checkpoint_row(ViewerState& st, SimWorker& worker) {
  const float w = 48, gap = ImGui::GetStyle().ItemSpacing.x;
  const std::string fallback = default_checkpoint_dir(st);
  ImGui::SetNextItemWidth(-2 * (w + gap));
  ImGui::InputTextWithHint("##checkpoint", fallback.c_str(), st.checkpoint_path,
                           sizeof st.checkpoint_path);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("checkpoint folder");
  const std::string dir = st.checkpoint_path[0] ? std::string(st.checkpoint_path) : fallback;
  ImGui::SameLine();
  if (ImGui::Button("Save", ImVec2(w, 0))) save_pane_checkpoints(st, worker, dir);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "save the pane as a run's checkpoint into this folder (several panes: "
        "FOLDER/pane-1, ...); apiclab run --resume FOLDER continues it");
  ImGui::SameLine();
  if (ImGui::Button("Load", ImVec2(w, 0))) open_checkpoint(st, worker, dir);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "open a run's checkpoint (run --checkpoint-every, or Save) as a pane, "
        "paused where the run stood");
}

void playback_section(ViewerState& st, const Published& pub, SimWorker& worker) {
  section("Run");
  const float w = (ImGui::GetContentRegionAvail().x - 2 * ImGui::GetStyle().ItemSpacing.x) / 3;
  if (ImGui::Button(pub.playing ? "Pause" : "Play", ImVec2(w, 0))) worker.play(!pub.playing);
  ImGui::SameLine();
  if (ImGui::Button("Step", ImVec2(w, 0))) worker.step_frame();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("advance one frame (1/fps of simulated time)");
  ImGui::SameLine();
  if (ImGui::Button("Reset", ImVec2(w, 0))) worker.reset(), st.notice.clear();
  if (ImGui::RadioButton("real time", st.realtime)) st.realtime = true, worker.set_realtime(true);
  ImGui::SameLine();
  if (ImGui::RadioButton("as fast as possible", !st.realtime))
    st.realtime = false, worker.set_realtime(false);
  const double t = pub.panes.empty() ? 0 : pub.panes[0].snapshot->time;
  const double end = pub.scene ? pub.scene->time.end : 0;
  char progress[64];  // %g: a time of 1e+30 (a fixed step that large) reads as such, not "1000000"
  std::snprintf(progress, sizeof progress, "%.6g / %.6g s", t, end);
  ImGui::ProgressBar(end > 0 ? float(std::min(t / end, 1.0)) : 0, ImVec2(-1, 0), progress);
  // Throughput while the panes step; nothing while they do not (paused, finished, a grid
  // method's particle-steps): a 0 there read as a measurement.
  if (pub.sim_seconds_per_wall_second > 0)
    ImGui::Text("%s sim s / wall s", human(pub.sim_seconds_per_wall_second, "").c_str());
  if (pub.particle_steps_per_second > 0)
    ImGui::Text("%s particle-steps/s", human(pub.particle_steps_per_second, "").c_str());
  // Wrapped: a slow frame's long numbers must not run past a narrow panel.
  ImGui::TextWrapped("display %.0f fps (%.1f ms/frame, GUI CPU %.1f ms)",
                     st.frame_ms > 0 ? 1000 / st.frame_ms : 0, st.frame_ms, st.frame_cpu_ms);
  checkpoint_row(st, worker);
  if (!pub.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kError);
    ImGui::TextWrapped("%s", pub.error.c_str());
    ImGui::PopStyleColor();
  }
  if (!pub.notice.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kNote);
    ImGui::TextWrapped("%s", pub.notice.c_str());
    ImGui::PopStyleColor();
  }
  if (!st.notice.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kNote);
    ImGui::TextWrapped("%s", st.notice.c_str());
    ImGui::PopStyleColor();
  }
}

// One combo for a pane's solver: the MPM schemes, then the methods without schemes. Returns
// whether the pick changed c.scheme or c.method.
bool pane_combo(PaneConfig& c, const std::string& method) {
  const std::string shown = method == "mpm" ? std::string(key_of(c.scheme)) : method;
  bool changed = false;
  if (!ImGui::BeginCombo("##scheme", shown.c_str())) return false;
  for (const auto& choice : scheme_choices())
    if (ImGui::Selectable(std::string(choice.key).c_str(),
                          method == "mpm" && c.scheme == choice.value)) {
      changed = method != "mpm" || c.scheme != choice.value;
      c.method = "mpm", c.scheme = choice.value;
    }
  for (const std::string& name : method_names())
    if (name != "mpm" && ImGui::Selectable(name.c_str(), method == name)) {
      changed = method != name;
      c.method = name;
    }
  ImGui::EndCombo();
  return changed;
}

void panes_section(ViewerState& st, const Published& pub, SimWorker& worker) {
  section("Panes: scheme switches live");
  for (std::size_t k = 0; k < st.panes.size(); ++k) {
    PaneConfig& c = st.panes[k];
    ImGui::PushID(int(k));
    ImGui::ColorButton("##c", ImGui::ColorConvertU32ToFloat4(pane_color(k)),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
    ImGui::SameLine();
    ImGui::SetNextItemWidth(80);
    const std::string method = c.method.empty() ? st.scene.solver.method : c.method;
    if (pane_combo(c, method)) {
      if ((c.method.empty() ? st.scene.solver.method : c.method) != method)
        restart_because(st, worker, "Pane method");  // another solver: new simulation
      else
        worker.set_scheme(k, c.scheme, c.flip_alpha);
    }
    const bool mpm = (c.method.empty() ? st.scene.solver.method : c.method) == "mpm";
    if (mpm && blends_flip(c.scheme)) {
      ImGui::SameLine();
      ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - (st.panes.size() > 1 ? 30 : 0));
      // Live, so not through a restart; the slider stays inside the registry's closed range.
      const NumericParameter& alpha = *find_parameter("solver.flip_alpha");
      float a = float(c.flip_alpha);
      if (ImGui::SliderFloat("##alpha", &a, float(alpha.range.lo), float(alpha.range.hi),
                             "\u03B1 %.2f") &&
          alpha.range.contains(a))
        c.flip_alpha = a, worker.set_scheme(k, c.scheme, a);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", alpha.describe().c_str());
    }
    if (st.panes.size() > 1) {
      ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 22);
      if (ImGui::SmallButton("x")) {
        st.panes.erase(st.panes.begin() + std::ptrdiff_t(k));
        restart_because(st, worker, "Panes");
        ImGui::PopID();
        break;
      }
    }
    if (!mpm) {  // kernel and integrator are MPM's; an EoL pane has none of its controls
      ImGui::PopID();
      continue;
    }
    ImGui::Indent(18);
    // Kernel 43 %, integrator 57 %: the longest texts, "kernel: quadratic" and
    // "integrator: symplectic", both fit the column.
    const float both = ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x;
    ImGui::SetNextItemWidth(std::round(0.43f * both));
    const std::string scene_kernel(choice_key(kernel_choices(), st.scene.solver.kernel));
    if (optional_combo("##kernel", c.kernel, kernel_choices(), "kernel", scene_kernel))
      restart_because(st, worker, "Pane kernel");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("kernel for this pane (restarts)");
    record(st, "pane " + std::to_string(k) + " kernel", ImGui::GetItemRectMin(),
           ImGui::GetItemRectMax());
    record_text(st, "pane " + std::to_string(k) + " kernel text",
                "kernel: " + (c.kernel ? std::string(choice_key(kernel_choices(), *c.kernel))
                                       : scene_kernel));
    ImGui::SameLine();
    ImGui::SetNextItemWidth(both - std::round(0.43f * both));
    const std::string scene_integrator(
        choice_key(integrator_choices(), st.scene.solver.integrator));
    if (optional_combo("##integrator", c.integrator, integrator_choices(), "integrator",
                       scene_integrator))
      restart_because(st, worker, "Pane integrator");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("integrator for this pane (restarts)");
    record(st, "pane " + std::to_string(k) + " integrator", ImGui::GetItemRectMin(),
           ImGui::GetItemRectMax());
    record_text(st, "pane " + std::to_string(k) + " integrator text",
                "integrator: " + (c.integrator
                                      ? std::string(choice_key(integrator_choices(), *c.integrator))
                                      : scene_integrator));
    ImGui::Unindent(18);
    ImGui::PopID();
  }
  if (st.scene_loaded && st.panes.size() < 4 &&
      ImGui::Button("+ add pane (restarts)", ImVec2(-1, 0))) {
    PaneConfig next = st.panes.empty() ? PaneConfig{} : st.panes.back();
    next.scheme = Scheme((int(next.scheme) + 1) % int(scheme_choices().size()));
    st.panes.push_back(next);
    restart_because(st, worker, "Panes");
  }
}

void solver_section(ViewerState& st, SimWorker& worker) {
  section("Solver (changes restart)");
  SceneDesc& s = st.scene;
  ImGui::PushItemWidth(-170);
  if (choice_combo("kernel", s.solver.kernel, kernel_choices()))
    restart_because(st, worker, "Kernel");
  if (choice_combo("integrator", s.solver.integrator, integrator_choices())) {
    // solver.lambda belongs to the lambda integrator alone (sim/scene/parameters.cpp).
    if (s.solver.integrator != Integrator::lambda_family)
      s.solver.lambda.reset();
    else if (!s.solver.lambda)
      s.solver.lambda = 0.5;
    restart_because(st, worker, "Integrator");
  }
  parameter_field(st, worker, "time.end");
  if (choice_combo("time step", s.time.rule, dt_rule_choices()))
    restart_because(st, worker, "Time-step rule");
  if (s.time.rule == DtRule::fixed) {
    parameter_field(st, worker, "time.dt.value");
  } else {
    parameter_field(st, worker, "time.dt.nu");
  }
  if (s.time.rule == DtRule::two_step) {
    parameter_field(st, worker, "time.dt.min");
    parameter_field(st, worker, "time.dt.value");
    parameter_field(st, worker, "time.dt.v_tau");
  }
  if (s.solver.integrator == Integrator::lambda_family)
    parameter_field(st, worker, "solver.lambda");
  if (s.solver.integrator != Integrator::symplectic || s.solver.integrator_lambda() != 0) {
    for (const char* key : {"solver.newton_tolerance", "solver.newton_max_iterations",
                            "solver.cg_tolerance", "solver.cg_max_iterations"})
      parameter_field(st, worker, key);
    if (choice_combo("CG preconditioner", s.solver.preconditioner, cg_preconditioner_choices()))
      restart_because(st, worker, "CG preconditioner");
  }
  // The parameters of the panes' schemes, scene-wide, while a pane runs the scheme: XPIC's m,
  // PolyPIC's modes, ASFLIP's beta (its alpha is the pane's slider).
  bool runs[3] = {false, false, false};
  for (const PaneConfig& c : st.panes)
    if ((c.method.empty() ? s.solver.method : c.method) == "mpm") {
      runs[0] |= c.scheme == Scheme::xpic;
      runs[1] |= c.scheme == Scheme::polypic;
      runs[2] |= c.scheme == Scheme::asflip;
    }
  const char* scheme_keys[3] = {"solver.xpic_order", "solver.polypic_modes", "solver.asflip_beta"};
  for (int k = 0; k < 3; ++k)
    if (runs[k]) parameter_field(st, worker, scheme_keys[k]);
  for (std::size_t m = 0; m < s.materials.size(); ++m) {
    MaterialDesc& mat = s.materials[m];
    ImGui::PushID(int(m));
    ImGui::TextColored(kMuted, "material '%s'", mat.name.c_str());
    if (choice_combo("model", mat.model, material_choices()))
      restart_because(st, worker, "Material model");
    for (const char* field : {"E", "nu", "rho"})
      parameter_field(st, worker, "materials." + std::to_string(m) + "." + field);
    ImGui::PopID();
  }
  ImGui::PopItemWidth();
}

// The configurations of a sweep run and its reference, as the runner gave them to `run`.
void sweep_section(const ViewerState& st) {
  section("Sweep runs (each its own configuration)");
  if (!st.sweep || st.sweep_run < 0) return;
  const std::size_t run = std::size_t(st.sweep_run);
  const std::size_t ref = st.sweep->plan.runs[run].reference;
  for (const std::size_t i : {ref, run}) {
    if (i == run && run == ref) break;
    const sweep::PlannedRun& p = st.sweep->plan.runs[i];
    ImGui::TextColored(kMuted, "%s %s", i == ref ? "reference" : "run", p.id.c_str());
    std::string sets;
    for (const std::string& o : p.overrides) sets += "  --set " + o + "\n";
    ImGui::PushStyleColor(ImGuiCol_Text, kMuted);
    ImGui::TextWrapped("%s\n%s", std::filesystem::path(p.scene_path).stem().c_str(), sets.c_str());
    ImGui::PopStyleColor();
  }
}

void view_section(ViewerState& st, const Published& pub, SimWorker& worker) {
  section("View");
  ImGui::PushItemWidth(-110);
  if (choice_combo("color", st.color, color_mode_choices())) {
    st.color_max = 0, st.scaled_for = nullptr;
    worker.set_noise(st.color == render::ColorMode::noise);
  }
  if (render::is_scalar(st.color)) {
    ImGui::Checkbox("auto scale", &st.auto_scale);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    if (ImGui::DragFloat("##cmax", &st.color_max, st.color_max * 0.01f + 1e-6f, kColorMax.lo,
                         kColorMax.hi, "max %.3g", ImGuiSliderFlags_AlwaysClamp))
      st.auto_scale = false;
    st.color_max = within(st.color_max, kColorMax);
  }
  ImGui::Checkbox("velocity vectors", &st.vectors);
  ImGui::SameLine();
  ImGui::Checkbox("grid", &st.grid);
  ImGui::Checkbox("surface", &st.surface);
  ImGui::SameLine();
  ImGui::Checkbox("surface vectors", &st.surface_vectors);
  // Typed values (ctrl+click) are clamped too, and a NaN replaced (app/gui/view_limits.hpp).
  constexpr ImGuiSliderFlags kFlags = ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp;
  ImGui::SliderFloat("arrow length", &st.vector_gain, kVectorGain.lo, kVectorGain.hi, "x%.2f",
                     kFlags);
  st.vector_gain = within(st.vector_gain, kVectorGain);
  ImGui::SliderFloat("particle size", &st.particle_scale, kParticleScale.lo, kParticleScale.hi,
                     "x%.2f", kFlags);
  st.particle_scale = within(st.particle_scale, kParticleScale);
  ImGui::PopItemWidth();
  if (ImGui::Button("Frame domain", ImVec2(-1, 0))) st.framed_generation = ~std::uint64_t(0);
  (void)pub;
}

}  // namespace

void draw_controls(ViewerState& st, const Published& pub, SimWorker& worker) {
  ImGui::Begin("Controls", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoBringToFrontOnFocus);
  // The header wraps within the column instead of running under its edge.
  const ImVec2 header = ImGui::GetCursorScreenPos();
  ImGui::TextColored(ImVec4(0.1f, 0.1f, 0.1f, 1), "apiclab");
  ImGui::SameLine();
  ImGui::PushStyleColor(ImGuiCol_Text, kMuted);
  ImGui::PushTextWrapPos(0);
  ImGui::TextUnformatted("particle/grid transfers and Eulerian-on-Lagrangian");
  ImGui::PopTextWrapPos();
  ImGui::PopStyleColor();
  record(st, "header", header, ImGui::GetItemRectMax());
  scene_section(st, worker);
  playback_section(st, pub, worker);
  panes_section(st, pub, worker);
  // Panes with scenes of their own (a sweep run and its reference) take no scene-wide edits.
  const bool own_scenes = std::any_of(st.panes.begin(), st.panes.end(),
                                      [](const PaneConfig& c) { return c.scene != nullptr; });
  if (st.scene_loaded && !own_scenes) solver_section(st, worker);
  if (own_scenes) sweep_section(st);
  view_section(st, pub, worker);
  ImGui::End();
}

}  // namespace apiclab::gui
