#include "app/figures/chart_style.hpp"

#include "render/figure.hpp"
#include "render/palette.hpp"

namespace apiclab::figures {

SchemeStyle style_of(const std::string& key) {
  return {render::scheme_label(key), render::packed_abgr(render::scheme_color(key))};
}

SchemeStyle style_of(const std::string& key, const SchemeParameters& parameters,
                     double flip_alpha) {
  SchemeStyle s = style_of(key);
  s.label = render::scheme_label(key, flip_alpha, parameters);
  return s;
}

float heading(ChartCanvas& canvas, const std::string& text, float width) {
  ImGui::PushFont(canvas.title_font());
  const ImVec2 ts = ImGui::CalcTextSize(text.c_str());
  ImGui::GetWindowDrawList()->AddText(ImVec2((width - ts.x) / 2, 6), IM_COL32(20, 20, 20, 255),
                                      text.c_str());
  ImGui::PopFont();
  return ts.y + 12;
}

}  // namespace apiclab::figures
