#include "app/gui/scene_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/gui/view_limits.hpp"
#include "render/figure.hpp"
#include "render/legend.hpp"
#include "render/snapshot_stats.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"

namespace apiclab::gui {
namespace {

constexpr float kTitle = 26;                       // pane title strip, pixels
constexpr float kHint = 22;                        // strip under the panes: how to move the camera
constexpr float kLegendFont = 13, kLegendPad = 8;  // the renderer's legend, pixels

render::Rect scene_rect(render::Rect pane) {
  return {pane.x, pane.y + kTitle, pane.w, pane.h - kTitle};
}
bool inside(render::Rect r, ImVec2 p) {
  return p.x >= r.x && p.y >= r.y && p.x < r.x + r.w && p.y < r.y + r.h;
}

// The scales follow the panes' snapshots (render/auto_scale.hpp, the PNGs' rules); they are
// updated once per new snapshot, not once per displayed frame.
void update_scales(ViewerState& st, const Published& pub) {
  const Snapshot* first = pub.panes.empty() ? nullptr : pub.panes[0].snapshot.get();
  if (first == st.scaled_for) return;
  st.scaled_for = first;
  std::vector<const Snapshot*> snapshots;
  for (const PaneState& p : pub.panes) snapshots.push_back(p.snapshot.get());
  render::update_scales(st.scales, snapshots);
}

render::Camera camera_for(const ViewerState& st, const Snapshot& s, render::Rect r) {
  return render::make_camera(st.view, r.w / std::max(r.h, 1.0f), render::domain_box(s));
}

// Pixel position of world point p in rect r, and whether it is in front of the camera.
bool project(const render::Camera& cam, render::Rect r, render::Vec3 p, ImVec2& out) {
  const render::Vec4 c = cam.projection * (cam.view * render::Vec4{p.x, p.y, p.z, 1});
  if (c.w <= 0) return false;
  out = ImVec2(r.x + (c.x / c.w * 0.5f + 0.5f) * r.w, r.y + (0.5f - c.y / c.w * 0.5f) * r.h);
  return true;
}

void handle_input(ViewerState& st, const Snapshot& s, render::Rect r, bool mouse_here) {
  ImGuiIO& io = ImGui::GetIO();
  if (!mouse_here || io.WantCaptureMouse) return;
  if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) {
    st.framed_generation = ~std::uint64_t(0);  // re-frame next time
    return;
  }
  const ImVec2 d = io.MouseDelta;
  const bool left = ImGui::IsMouseDown(ImGuiMouseButton_Left);
  const bool other =
      ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle);
  render::View& v = st.view;
  if (s.dim == 2) {
    const float per_px = 2 * v.half_height / r.h;
    if (left || other) v.center.x -= d.x * per_px, v.center.y += d.y * per_px;
    if (io.MouseWheel != 0) {  // zoom about the cursor: the point under it stays put
      const float mx = (io.MousePos.x - (r.x + r.w / 2)) * per_px;
      const float my = ((r.y + r.h / 2) - io.MousePos.y) * per_px;
      const float f = std::pow(0.88f, io.MouseWheel);
      v.center.x += mx * (1 - f), v.center.y += my * (1 - f);
      v.half_height = within(v.half_height * f, kViewSize);
    }
    return;
  }
  if (left) v.yaw -= d.x * 0.35f, v.pitch = std::clamp(v.pitch + d.y * 0.35f, -89.0f, 89.0f);
  if (other) {
    render::Vec3 right, up, back;
    render::orbit_axes(v, right, up, back);
    const float per_px = 2 * v.distance * std::tan(render::radians(v.fov_y) / 2) / r.h;
    v.target = v.target - right * (d.x * per_px) + up * (d.y * per_px);
  }
  if (io.MouseWheel != 0)
    v.distance = within(v.distance * std::pow(0.88f, io.MouseWheel), kViewSize);
}

// The particle nearest the cursor within a few pixels, or -1.
long pick(const Snapshot& s, const render::Camera& cam, render::Rect r, ImVec2 m) {
  long best = -1;
  float best_d2 = 10 * 10;
  for (std::size_t i = 0; i < s.count(); ++i) {
    const float* x = &s.positions[i * s.dim];
    ImVec2 p;
    if (!project(cam, r, {x[0], x[1], s.dim == 3 ? x[2] : 0.0f}, p)) continue;
    const float d2 = (p.x - m.x) * (p.x - m.x) + (p.y - m.y) * (p.y - m.y);
    if (d2 < best_d2) best_d2 = d2, best = long(i);
  }
  return best;
}

void particle_tooltip(const Snapshot& s, std::size_t i) {
  ImGui::BeginTooltip();
  ImGui::Text("particle %zu", i);
  const int m = s.material.empty() ? 0 : s.material[i];
  ImGui::Text("object %d, material %s", s.object.empty() ? 0 : s.object[i],
              m < int(s.material_names.size()) ? s.material_names[size_t(m)].c_str() : "?");
  const float* x = &s.positions[i * s.dim];
  const float* v = &s.velocities[i * s.dim];
  if (s.dim == 2) {
    ImGui::Text("x = (%.5g, %.5g)", x[0], x[1]);
    ImGui::Text("v = (%.5g, %.5g)", v[0], v[1]);
  } else {
    ImGui::Text("x = (%.5g, %.5g, %.5g)", x[0], x[1], x[2]);
    ImGui::Text("v = (%.5g, %.5g, %.5g)", v[0], v[1], v[2]);
  }
  ImGui::Text("|v| = %.5g", render::particle_speed(s, i));
  if (!s.noise.empty()) ImGui::Text("noise |v - v_PIC| = %.4g", s.noise[i]);
  ImGui::EndTooltip();
}

// `text`, or as much of it as fits in `width` pixels followed by "...".
std::string cut_text(const std::string& text, float width) {
  if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
  std::string cut = text;
  while (!cut.empty() && ImGui::CalcTextSize((cut + "...").c_str()).x > width) cut.pop_back();
  return cut + "...";
}

// A pane's title strip: its label and, right-aligned, its details (kernel / integrator, time,
// step) or, once it blew up, where (step and time; the quantity when there is room). The
// details drop their least important parts when the pane is narrow; the label gives way to a
// blow-up's time, cut with "...".
struct TitleStrip {
  std::string label, info;
  bool failed = false;
};
TitleStrip title_strip(const PaneState& p, const Snapshot& s, float width) {
  TitleStrip t;
  t.label = pane_label(p);
  char full[160], brief[80];
  std::snprintf(full, sizeof full, "t = %.4g s   step %ld", s.time, s.step);
  std::snprintf(brief, sizeof brief, "t = %.4g s", s.time);
  t.info = s.kernel + " / " + s.integrator + "   " + full;
  float label_room = ImGui::CalcTextSize(t.label.c_str()).x;
  if (p.failure) {
    std::snprintf(full, sizeof full, "blew up at step %ld, t = %.4g s", p.failure->step,
                  p.failure->t);
    std::snprintf(brief, sizeof brief, "blew up at t = %.4g s", p.failure->t);
    t.info = std::string(full) + ": " + p.failure->quantity;
    t.failed = true;
    label_room = std::min(label_room, 60.0f);
  }
  const float room = width - 48 - label_room;
  for (const char* shorter : {full, brief})
    if (ImGui::CalcTextSize(t.info.c_str()).x > room) t.info = shorter;
  // What is left beside the details; too little for a letter and "...": the chip alone (the
  // label is in the tooltip).
  const float label_width = width - 48 - ImGui::CalcTextSize(t.info.c_str()).x;
  t.label = label_width < ImGui::CalcTextSize("M...").x ? "" : cut_text(t.label, label_width);
  return t;
}

// What the pane runs that a person should know while watching it: PolyPIC keeping its G modes
// (the warning `run` prints).
std::string pane_warning(const Snapshot& s) {
  const int kept = s.scheme_parameters.polypic_modes, dim = s.dim;
  if (s.scheme != "polypic" || !polypic::keeps_g_modes(kept, dim)) return "";
  return "PolyPIC with " + std::to_string(kept) +
         " modes keeps the G modes, which blow up where stressed material meets nearly empty "
         "grid nodes (impacts, contact); impacts run with solver.polypic_modes=" +
         std::to_string(1 << dim) + " or fewer";
}

void draw_hint(render::Rect r) {
  const char* hint = "drag: pan/orbit   wheel: zoom   double-click: frame";
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  dl->AddLine(ImVec2(r.x, r.y), ImVec2(r.x + r.w, r.y), IM_COL32(210, 210, 210, 255));
  dl->AddText(ImVec2(r.x + r.w - 14 - ImGui::CalcTextSize(hint).x, r.y + 3),
              IM_COL32(130, 130, 130, 255), hint);
}

}  // namespace

std::vector<render::Rect> pane_scene_rects(render::Rect area, std::size_t n) {
  std::vector<render::Rect> out;
  const float w = area.w / float(std::max<std::size_t>(n, 1));
  for (std::size_t k = 0; k < n; ++k)
    out.push_back(scene_rect({std::round(area.x + w * k), area.y, std::round(w), area.h}));
  return out;
}

render::FigureStyle figure_style(const ViewerState& st, int up_axis) {
  render::FigureStyle style;
  style.color = st.color;
  style.color_max = st.auto_scale ? 0 : st.color_max;
  style.vectors = st.vectors;
  style.vector_gain = st.vector_gain;
  style.grid = st.grid;
  style.surface = st.surface;
  style.surface_vectors = st.surface_vectors;
  style.particle_scale = st.particle_scale;
  style.up_axis = up_axis;
  return style;
}

std::vector<render::Rect> draw_scene_panes(render::Renderer& r, ViewerState& st,
                                           const Published& pub, render::Rect area) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  if (pub.panes.empty()) {
    const char* msg =
        st.load_error.empty() ? "Loading scene..." : "No scene: see the error on the left.";
    const ImVec2 ts = ImGui::CalcTextSize(msg);
    dl->AddText(ImVec2(area.x + (area.w - ts.x) / 2, area.y + area.h / 2),
                IM_COL32(90, 90, 90, 255), msg);
    return {};
  }
  const Snapshot& first = *pub.panes[0].snapshot;
  const int up_axis = pub.scene ? render::up_axis_from_gravity(pub.scene->gravity, first.dim) : 1;
  const render::FigureStyle wanted = figure_style(st, up_axis);
  // The legend is the renderer's, as in the PNGs, in a column right of the panes.
  const float legend_w = render::legend_width(r, kLegendFont, kLegendPad, st.color,
                                              st.vectors || st.surface_vectors, first);
  const render::Rect panes_area{area.x, area.y, area.w - legend_w, area.h - kHint};
  const render::Rect legend{area.x + area.w - legend_w, area.y + kTitle, legend_w,
                            area.h - kHint - kTitle};
  const auto rects = pane_scene_rects(panes_area, pub.panes.size());
  if (st.framed_generation != pub.generation) {  // new scene or reset: frame the domain
    st.view =
        render::frame_view(first.dim, render::domain_box(first), rects[0].w / rects[0].h, up_axis);
    st.framed_generation = pub.generation;
    st.scales.reset();
    st.scaled_for = nullptr;
  }
  update_scales(st, pub);
  std::vector<const Snapshot*> snapshots;
  for (const PaneState& p : pub.panes) snapshots.push_back(p.snapshot.get());
  const render::SceneStyle style =
      render::resolve_scene_style(wanted, snapshots, rects[0], st.scales);
  if (st.auto_scale) st.color_max = style.color_max;  // the controls show the scale in use

  const ImVec2 mouse = ImGui::GetIO().MousePos;
  for (std::size_t k = 0; k < pub.panes.size(); ++k) {
    const PaneState& p = pub.panes[k];
    const render::Rect sr = rects[k];
    handle_input(st, *p.snapshot, sr, inside(sr, mouse));
  }
  float pixels_per_unit = 0;
  for (std::size_t k = 0; k < pub.panes.size(); ++k) {
    const PaneState& p = pub.panes[k];
    const Snapshot& s = *p.snapshot;
    const render::Rect sr = rects[k];
    const render::Camera cam = camera_for(st, s, sr);
    pixels_per_unit = render::draw_pane_scene(r, s, st.view, sr, style);

    // Title strip: color chip, scheme, time.
    const ImVec2 t0(sr.x, sr.y - kTitle), t1(sr.x + sr.w, sr.y);
    dl->AddRectFilled(t0, t1, IM_COL32(244, 245, 247, 255));
    dl->AddLine(ImVec2(t0.x, t1.y), t1, IM_COL32(215, 215, 215, 255));
    dl->AddRectFilled(ImVec2(t0.x + 10, t0.y + 8), ImVec2(t0.x + 20, t0.y + 18), pane_color(k), 2);
    const TitleStrip strip = title_strip(p, s, sr.w);
    const float info_x = std::max(t0.x + 28, t1.x - 10 - ImGui::CalcTextSize(strip.info.c_str()).x);
    dl->AddText(ImVec2(info_x, t0.y + 5),
                strip.failed ? IM_COL32(200, 30, 30, 255) : IM_COL32(100, 100, 100, 255),
                strip.info.c_str());
    dl->AddText(ImVec2(t0.x + 28, t0.y + 5), IM_COL32(20, 20, 20, 255), strip.label.c_str());
    if (ImGui::IsMouseHoveringRect(t0, ImVec2(info_x - 12, t1.y)))
      ImGui::SetTooltip("%s", pane_label(p).c_str());  // the whole label on demand
    if (p.failure && ImGui::IsMouseHoveringRect(ImVec2(info_x, t0.y), t1))
      ImGui::SetTooltip("%s", p.failure->message.c_str());  // the whole message on demand
    st.layout["pane " + std::to_string(k) + " title"] =
        ImVec4(t0.x + 28, t0.y + 5, ImGui::CalcTextSize(strip.label.c_str()).x, 16);
    st.layout_text["pane " + std::to_string(k)] = pane_label(p) + " | " + strip.info;
    st.layout["pane " + std::to_string(k) + " details"] =
        ImVec4(info_x, t0.y + 5, ImGui::CalcTextSize(strip.info.c_str()).x, 16);
    const std::string warning = pane_warning(s);
    if (!warning.empty()) {  // a strip at the pane's foot, the whole text on hover
      const float fh = ImGui::GetFontSize();
      const ImVec2 w0(sr.x, sr.y + sr.h - fh - 8), w1(sr.x + sr.w, sr.y + sr.h);
      dl->AddRectFilled(w0, w1, IM_COL32(255, 243, 205, 235));
      const std::string shown = cut_text(warning, sr.w - 16);
      dl->AddText(ImVec2(w0.x + 8, w0.y + 4), IM_COL32(140, 80, 0, 255), shown.c_str());
      if (ImGui::IsMouseHoveringRect(w0, w1)) ImGui::SetTooltip("%s", warning.c_str());
      st.layout["pane " + std::to_string(k) + " warning"] =
          ImVec4(w0.x, w0.y, w1.x - w0.x, w1.y - w0.y);
    }
    if (k > 0)
      dl->AddLine(ImVec2(t0.x, t0.y), ImVec2(t0.x, sr.y + sr.h), IM_COL32(200, 200, 200, 255));

    if (inside(sr, mouse) && !ImGui::GetIO().WantCaptureMouse &&
        !ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      const long i = pick(s, cam, sr, mouse);
      if (i >= 0) particle_tooltip(s, std::size_t(i));
    }
  }
  render::draw_legend(r, legend, kLegendFont, kLegendPad, style, first, pixels_per_unit);
  draw_hint({area.x, area.y + area.h - kHint, area.w, kHint});
  return rects;
}

}  // namespace apiclab::gui
