#include "render/text.hpp"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#define STB_RECT_PACK_IMPLEMENTATION
#define STB_TRUETYPE_IMPLEMENTATION
#define STBTT_STATIC
#include <stb/stb_rect_pack.h>
#include <stb/stb_truetype.h>

#include "render/resources.hpp"

namespace apiclab::render {

// Latin-1 and Greek for labels like "FLIP α=0.95"; a few symbols for units and ranges.
namespace {
constexpr char32_t kSymbols[] = {0x2013, 0x2014, 0x2026, 0x2016, 0x2192, 0x2212,
                                 0x2248, 0x2264, 0x2265, 0x221E, 0x2207, 0x2202};
}

struct Font::Glyphs {
  stbtt_fontinfo info{};
  float scale = 1;
  std::unordered_map<char32_t, stbtt_packedchar> chars;
  std::unordered_map<char32_t, int> glyph_index;
};

char32_t next_code_point(std::string_view s, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  unsigned char c = byte(i++);
  if (c < 0x80) return c;
  int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : -1;
  if (extra < 0 || i + extra > s.size()) return 0xFFFD;
  char32_t cp = c & (0x3F >> extra);
  for (int k = 0; k < extra; ++k) {
    unsigned char b = byte(i);
    if ((b & 0xC0) != 0x80) return 0xFFFD;
    cp = (cp << 6) | (b & 0x3F);
    ++i;
  }
  return cp;
}

Font::Font(float pixel_height) : glyphs_(std::make_unique<Glyphs>()), pixel_height_(pixel_height) {
  std::string_view ttf = resource("fonts/DejaVuSans.ttf");
  const auto* data = reinterpret_cast<const unsigned char*>(ttf.data());
  if (!stbtt_InitFont(&glyphs_->info, data, stbtt_GetFontOffsetForIndex(data, 0)))
    throw std::runtime_error("embedded font DejaVuSans.ttf is unreadable");
  glyphs_->scale = stbtt_ScaleForPixelHeight(&glyphs_->info, pixel_height);
  int ascent, descent, gap;
  stbtt_GetFontVMetrics(&glyphs_->info, &ascent, &descent, &gap);
  ascent_ = ascent * glyphs_->scale;
  descent_ = -descent * glyphs_->scale;
  line_gap_ = gap * glyphs_->scale;

  std::vector<int> code_points;
  for (int c = 0x20; c <= 0x7E; ++c) code_points.push_back(c);
  for (int c = 0xA0; c <= 0xFF; ++c) code_points.push_back(c);
  for (int c = 0x391; c <= 0x3C9; ++c) code_points.push_back(c);
  for (char32_t c : kSymbols) code_points.push_back(int(c));
  std::vector<stbtt_packedchar> packed(code_points.size());
  stbtt_pack_range range{};
  range.font_size = pixel_height;
  range.array_of_unicode_codepoints = code_points.data();
  range.num_chars = int(code_points.size());
  range.chardata_for_range = packed.data();

  // 2x horizontal oversampling keeps glyphs crisp at fractional pen positions; the atlas
  // grows until everything fits.
  for (int side = 256;; side *= 2) {
    if (side > 8192) throw std::runtime_error("font atlas too large");
    atlas_.assign(std::size_t(side) * side, 0);
    stbtt_pack_context pack;
    if (!stbtt_PackBegin(&pack, atlas_.data(), side, side, 0, 1, nullptr)) continue;
    stbtt_PackSetOversampling(&pack, 2, 1);
    int ok = stbtt_PackFontRanges(&pack, data, 0, &range, 1);
    stbtt_PackEnd(&pack);
    if (ok) {
      atlas_width_ = atlas_height_ = side;
      break;
    }
  }
  for (std::size_t k = 0; k < code_points.size(); ++k) {
    glyphs_->chars[char32_t(code_points[k])] = packed[k];
    glyphs_->glyph_index[char32_t(code_points[k])] =
        stbtt_FindGlyphIndex(&glyphs_->info, code_points[k]);
  }
}

Font::~Font() = default;

float Font::layout(std::string_view utf8, float x, float y, std::vector<Quad>& out) const {
  int previous = 0;
  for (std::size_t i = 0; i < utf8.size();) {
    char32_t cp = next_code_point(utf8, i);
    auto it = glyphs_->chars.find(cp);
    if (it == glyphs_->chars.end()) it = glyphs_->chars.find(U'?');
    int glyph = glyphs_->glyph_index.at(it->first);
    if (previous) x += glyphs_->scale * stbtt_GetGlyphKernAdvance(&glyphs_->info, previous, glyph);
    previous = glyph;
    stbtt_aligned_quad q;
    float pen_y = y;
    stbtt_GetPackedQuad(&it->second, atlas_width_, atlas_height_, 0, &x, &pen_y, &q, 0);
    if (q.x1 > q.x0) out.push_back({q.x0, q.y0, q.x1, q.y1, q.s0, q.t0, q.s1, q.t1});
  }
  return x;
}

float Font::width(std::string_view utf8) const {
  std::vector<Quad> quads;
  return layout(utf8, 0, 0, quads);
}

}  // namespace apiclab::render
