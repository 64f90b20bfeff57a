#include "app/figures/chart_style.hpp"

namespace apiclab::figures {
namespace {

constexpr SchemeStyle kSchemes[] = {
    {"pic", "PIC", IM_COL32(0, 114, 178, 255)},
    {"flip", "FLIP", IM_COL32(213, 94, 0, 255)},
    {"apic", "APIC", IM_COL32(0, 158, 115, 255)},
    {"rpic", "RPIC", IM_COL32(204, 121, 167, 255)},
};

}  // namespace

const SchemeStyle& style_of(const std::string& key) {
  for (auto& s : kSchemes)
    if (key == s.key) return s;
  return kSchemes[0];
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
