// The one categorical palette: materials, objects, GUI panes, plot series and the schemes'
// colours in figures all index it, so index k is the same colour everywhere. Okabe & Ito's
// colour-blind-safe colours, ordered so that the four schemes (pic, flip, apic, rpic) take
// the first four; each scheme names its slot in its own file (sim/mpm/schemes/).
// tests/render/figures_tests.sh repeats the schemes' hex values (a shell script cannot include
// this); test_render's Palette test pins them to the same strings.
#pragma once
#include <cctype>
#include <cstdint>
#include <string>
#include <string_view>

#include "render/color.hpp"
#include "sim/scene/scheme_registry.hpp"

namespace apiclab::render {

// Blue, vermillion, bluish green, reddish purple, orange, sky blue, yellow (Okabe & Ito), then
// indigo and wine (Tol's muted scheme) for the ninth and tenth scheme, and dark grey last (the
// colour of anything outside the table).
inline constexpr Rgba8 kPalette[] = {{0, 114, 178}, {213, 94, 0},   {0, 158, 115},  {204, 121, 167},
                                     {230, 159, 0}, {86, 180, 233}, {240, 228, 66}, {51, 34, 136},
                                     {136, 34, 85}, {60, 60, 60}};
inline constexpr int kPaletteSize = int(sizeof kPalette / sizeof kPalette[0]);

// Colour `index` of the palette, cycling (negative indices too).
constexpr Rgba8 palette_color(int index) {
  return kPalette[((index % kPaletteSize) + kPaletteSize) % kPaletteSize];
}

// A scheme by its registry key; nullptr for a key that names none.
constexpr const SchemeInfo* scheme_of_key(std::string_view key) {
  for (const SchemeInfo& s : kSchemes)
    if (s.key == key) return &s;
  return nullptr;
}

// The scheme's colour, the palette slot its file names; a key outside the registry gets grey.
constexpr Rgba8 scheme_color(std::string_view key) {
  const SchemeInfo* s = scheme_of_key(key);
  return palette_color(s ? s->colour : kPaletteSize - 1);
}

// "PIC", "FLIP", ... (the scheme's name); the methods "EoL" and "Eulerian"; a key outside these
// in upper case.
inline std::string scheme_label(std::string_view key) {
  if (const SchemeInfo* s = scheme_of_key(key)) return std::string(s->name);
  // The solver methods without schemes, as the manual writes them.
  if (key == "eol") return "EoL";
  if (key == "eulerian") return "Eulerian";
  std::string label(key);
  for (char& c : label) c = char(std::toupper(static_cast<unsigned char>(c)));
  return label;
}

// Packed as Dear ImGui's IM_COL32 packs (red in the low byte), without including ImGui.
constexpr std::uint32_t packed_abgr(Rgba8 c) {
  return std::uint32_t(c.r) | std::uint32_t(c.g) << 8 | std::uint32_t(c.b) << 16 |
         std::uint32_t(c.a) << 24;
}

}  // namespace apiclab::render
