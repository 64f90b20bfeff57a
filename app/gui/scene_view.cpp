#include "app/gui/scene_view.hpp"

#include "render/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace apiclab::gui {
namespace {

constexpr float kTitle = 26;  // pane title strip, pixels
constexpr float kLegend = 44; // legend strip under the panes

render::Rect scene_rect(render::Rect pane) { return {pane.x, pane.y + kTitle, pane.w, pane.h - kTitle}; }
bool inside(render::Rect r, ImVec2 p) { return p.x >= r.x && p.y >= r.y && p.x < r.x + r.w && p.y < r.y + r.h; }
ImU32 to_u32(render::Rgba8 c) { return IM_COL32(c.r, c.g, c.b, c.a); }

float speed(const Snapshot& s, std::size_t i) {
  float v2 = 0;
  for (int k = 0; k < s.dim; ++k) v2 += s.velocities[i * s.dim + k] * s.velocities[i * s.dim + k];
  return std::sqrt(v2);
}


// The color scale follows the 98th percentile over all panes and only grows, so colors
// mean the same thing from frame to frame and pane to pane.
void update_scales(ViewerState& st, const Published& pub) {
  const Snapshot* first = pub.panes.empty() ? nullptr : pub.panes[0].snapshot.get();
  if (first == st.scaled_for) return;
  st.scaled_for = first;
  if (!st.auto_scale || !render::is_scalar(st.color)) return;
  std::vector<float> v;
  for (auto& p : pub.panes) {
    const Snapshot& s = *p.snapshot;
    const std::size_t n = s.count(), stride = std::max<std::size_t>(1, n / 20000);
    for (std::size_t i = 0; i < n; i += stride)
      v.push_back(st.color == render::ColorMode::noise ? (s.noise.empty() ? 0 : s.noise[i]) : speed(s, i));
  }
  if (v.empty()) return;
  auto k = v.begin() + std::ptrdiff_t(0.98 * double(v.size() - 1));
  std::nth_element(v.begin(), k, v.end());
  st.color_max = std::max(st.color_max, render::nice_ceil(*k));
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
  const bool other = ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle);
  render::View& v = st.view;
  if (s.dim == 2) {
    const float per_px = 2 * v.half_height / r.h;
    if (left || other) v.center.x -= d.x * per_px, v.center.y += d.y * per_px;
    if (io.MouseWheel != 0) {  // zoom about the cursor: the point under it stays put
      const float mx = (io.MousePos.x - (r.x + r.w / 2)) * per_px;
      const float my = ((r.y + r.h / 2) - io.MousePos.y) * per_px;
      const float f = std::pow(0.88f, io.MouseWheel);
      v.center.x += mx * (1 - f), v.center.y += my * (1 - f);
      v.half_height *= f;
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
  if (io.MouseWheel != 0) v.distance *= std::pow(0.88f, io.MouseWheel);
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
  ImGui::Text("|v| = %.5g", speed(s, i));
  if (!s.noise.empty()) ImGui::Text("noise |v - v_PIC| = %.4g", s.noise[i]);
  ImGui::EndTooltip();
}

void draw_legend(ViewerState& st, const Published& pub, render::Rect r, float arrow_px_per_speed) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  dl->AddRectFilled(ImVec2(r.x, r.y), ImVec2(r.x + r.w, r.y + r.h), IM_COL32(250, 250, 250, 255));
  dl->AddLine(ImVec2(r.x, r.y), ImVec2(r.x + r.w, r.y), IM_COL32(210, 210, 210, 255));
  const float fh = ImGui::GetFontSize();
  float x = r.x + 14;
  const float y = r.y + 8;
  const ImU32 text = IM_COL32(40, 40, 40, 255);
  if (render::is_scalar(st.color)) {
    const char* title = st.color == render::ColorMode::speed ? "speed |v| [m/s]" : "noise |v - v_PIC| [m/s]";
    dl->AddText(ImVec2(x, y), text, title);
    x += ImGui::CalcTextSize(title).x + 12;
    const float w = 260, h = 12;
    for (int k = 0; k < 64; ++k) {  // the colormap as 64 gradient strips
      const ImU32 c0 = to_u32(render::to_rgba8(render::viridis(k / 64.0f)));
      const ImU32 c1 = to_u32(render::to_rgba8(render::viridis((k + 1) / 64.0f)));
      dl->AddRectFilledMultiColor(ImVec2(x + w * k / 64, y + 2), ImVec2(x + w * (k + 1) / 64 + 0.5f, y + 2 + h), c0, c1, c1, c0);
    }
    dl->AddRect(ImVec2(x, y + 2), ImVec2(x + w, y + 2 + h), IM_COL32(120, 120, 120, 255));
    char buf[32];
    for (int k = 0; k <= 4; ++k) {
      std::snprintf(buf, sizeof buf, "%.3g", st.color_max * k / 4);
      const float tx = x + w * k / 4, tw = ImGui::CalcTextSize(buf).x;
      dl->AddLine(ImVec2(tx, y + 2 + h), ImVec2(tx, y + 5 + h), IM_COL32(120, 120, 120, 255));
      dl->AddText(ImVec2(tx - tw / 2, y + h + 5), text, buf);
    }
    x += w + 30;
  } else if (!pub.panes.empty()) {
    const Snapshot& s = *pub.panes[0].snapshot;
    const bool by_material = st.color == render::ColorMode::material;
    int count = 0;
    for (auto o : by_material ? s.material : s.object) count = std::max(count, o + 1);
    for (int k = 0; k < count; ++k) {
      dl->AddCircleFilled(ImVec2(x + 6, y + fh / 2 + 4), 6, to_u32(render::category_color(k)));
      std::string name = by_material && k < int(s.material_names.size()) ? s.material_names[size_t(k)]
                                                                           : "object " + std::to_string(k);
      dl->AddText(ImVec2(x + 16, y + 4), text, name.c_str());
      x += ImGui::CalcTextSize(name.c_str()).x + 34;
    }
  }
  if (st.vectors && arrow_px_per_speed > 0) {  // an arrow of a round speed, to scale
    const float speed_ref = render::nice_ceil(std::max(st.color_max * 0.5f, 1e-6f));
    const float len = std::clamp(arrow_px_per_speed * speed_ref, 4.0f, 200.0f);
    const ImU32 col = IM_COL32(40, 40, 40, 255);
    dl->AddLine(ImVec2(x, y + 10), ImVec2(x + len, y + 10), col, 1.6f);
    dl->AddTriangleFilled(ImVec2(x + len + 1, y + 10), ImVec2(x + len - 6, y + 6), ImVec2(x + len - 6, y + 14), col);
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.3g m/s", speed_ref);
    dl->AddText(ImVec2(x + len + 8, y + 3), text, buf);
  }
  dl->AddText(ImVec2(r.x + r.w - 14 - ImGui::CalcTextSize("drag: pan/orbit   wheel: zoom   double-click: frame").x, y + 4),
              IM_COL32(130, 130, 130, 255), "drag: pan/orbit   wheel: zoom   double-click: frame");
}

}  // namespace

std::vector<render::Rect> pane_scene_rects(render::Rect area, std::size_t n) {
  std::vector<render::Rect> out;
  const float w = area.w / float(std::max<std::size_t>(n, 1));
  for (std::size_t k = 0; k < n; ++k)
    out.push_back(scene_rect({std::round(area.x + w * k), area.y, std::round(w), area.h}));
  return out;
}

void draw_scene_panes(render::Renderer& r, ViewerState& st, const Published& pub, render::Rect area) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const render::Rect panes_area{area.x, area.y, area.w, area.h - kLegend};
  const render::Rect legend{area.x, area.y + area.h - kLegend, area.w, kLegend};
  if (pub.panes.empty()) {
    const char* msg = st.load_error.empty() ? "Loading scene..." : "No scene: see the error on the left.";
    const ImVec2 ts = ImGui::CalcTextSize(msg);
    dl->AddText(ImVec2(area.x + (area.w - ts.x) / 2, area.y + area.h / 2), IM_COL32(90, 90, 90, 255), msg);
    return;
  }
  const auto rects = pane_scene_rects(panes_area, pub.panes.size());
  const Snapshot& first = *pub.panes[0].snapshot;
  if (st.framed_generation != pub.generation) {  // new scene or reset: frame the domain
    render::View v;
    v.dim = first.dim;
    v.up_axis = 1;
    if (pub.scene) {
      const auto& g = pub.scene->gravity;
      if (std::abs(g[2]) > std::abs(g[1]) && std::abs(g[2]) > std::abs(g[0])) v.up_axis = 2;
    }
    st.view = render::frame_view(v, render::domain_box(first), rects[0].w / rects[0].h);
    st.framed_generation = pub.generation;
    if (st.auto_scale) st.color_max = 0;
    st.scaled_for = nullptr;
  }
  update_scales(st, pub);

  render::SceneStyle style;
  style.color = st.color;
  style.color_max = std::max(st.color_max, 1e-6f);
  style.grid = st.grid;
  style.particle_scale = st.particle_scale;
  style.vectors = st.vectors;
  // An arrow of the top-of-scale speed spans about 1.6 cells.
  style.vector_scale = float(1.6 * first.dx) / style.color_max * st.vector_gain;
  style.vector_every = int(std::max<std::size_t>(1, first.count() / 450));

  const ImVec2 mouse = ImGui::GetIO().MousePos;
  for (std::size_t k = 0; k < pub.panes.size(); ++k) {
    const PaneState& p = pub.panes[k];
    const render::Rect sr = rects[k];
    handle_input(st, *p.snapshot, sr, inside(sr, mouse));
  }
  for (std::size_t k = 0; k < pub.panes.size(); ++k) {
    const PaneState& p = pub.panes[k];
    const Snapshot& s = *p.snapshot;
    const render::Rect sr = rects[k];
    const render::Camera cam = camera_for(st, s, sr);
    r.draw_scene(s, cam, sr, style);

    // Title strip: color chip, scheme, time.
    const ImVec2 t0(sr.x, sr.y - kTitle), t1(sr.x + sr.w, sr.y);
    dl->AddRectFilled(t0, t1, IM_COL32(244, 245, 247, 255));
    dl->AddLine(ImVec2(t0.x, t1.y), t1, IM_COL32(215, 215, 215, 255));
    dl->AddRectFilled(ImVec2(t0.x + 10, t0.y + 8), ImVec2(t0.x + 20, t0.y + 18), pane_color(k), 2);
    dl->AddText(ImVec2(t0.x + 28, t0.y + 5), IM_COL32(20, 20, 20, 255), pane_label(p).c_str());
    // Right-aligned details, dropping the least important when the pane is narrow.
    const float room = sr.w - 48 - ImGui::CalcTextSize(pane_label(p).c_str()).x;
    char buf[160];
    std::snprintf(buf, sizeof buf, "t = %.4g s   step %ld", s.time, s.step);
    std::string info = s.kernel + " / " + s.integrator + "   " + buf;
    if (ImGui::CalcTextSize(info.c_str()).x > room) info = buf;
    dl->AddText(ImVec2(t1.x - 10 - ImGui::CalcTextSize(info.c_str()).x, t0.y + 5), IM_COL32(100, 100, 100, 255),
                info.c_str());
    if (k > 0) dl->AddLine(ImVec2(t0.x, t0.y), ImVec2(t0.x, sr.y + sr.h), IM_COL32(200, 200, 200, 255));

    if (p.failure) {  // the pane is frozen: say where and why
      const Failure& f = *p.failure;
      std::snprintf(buf, sizeof buf, "BLEW UP at step %ld, t = %.5g s: %s", f.step, f.t, f.quantity.c_str());
      const float wrap = sr.w - 32, fh = ImGui::GetFontSize();
      const float msg_h = ImGui::CalcTextSize(f.message.c_str(), nullptr, false, wrap).y;
      const ImVec2 b0(sr.x + 8, sr.y + 8), b1(sr.x + sr.w - 8, sr.y + 20 + fh + msg_h);
      dl->AddRectFilled(b0, b1, IM_COL32(200, 30, 30, 230), 4);
      dl->AddText(ImVec2(b0.x + 8, b0.y + 4), IM_COL32(255, 255, 255, 255), buf);
      dl->AddText(nullptr, 0, ImVec2(b0.x + 8, b0.y + 6 + ImGui::GetFontSize()), IM_COL32(255, 230, 230, 255),
                  f.message.c_str(), nullptr, wrap);
    }
    if (inside(sr, mouse) && !ImGui::GetIO().WantCaptureMouse && !ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      const long i = pick(s, cam, sr, mouse);
      if (i >= 0) particle_tooltip(s, std::size_t(i));
    }
  }
  // Pixels per world unit at the scene's centre, for the arrow legend.
  const float world_h = first.dim == 2 ? 2 * st.view.half_height
                                       : 2 * st.view.distance * std::tan(render::radians(st.view.fov_y) / 2);
  draw_legend(st, pub, legend, style.vector_scale * rects[0].h / std::max(world_h, 1e-9f));
}

}  // namespace apiclab::gui
