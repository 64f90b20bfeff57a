// Text through a real font rasterizer: DejaVu Sans (embedded) baked by stb_truetype into a
// glyph atlas at one pixel size, with kerning; the renderer draws the quads.
#pragma once
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

namespace apiclab::render {

class Font {
 public:
  explicit Font(float pixel_height);  // throws std::runtime_error if the font is unusable
  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  float pixel_height() const { return pixel_height_; }
  float ascent() const { return ascent_; }    // above the baseline, pixels
  float descent() const { return descent_; }  // below the baseline, pixels (positive)
  float line_height() const { return ascent_ + descent_ + line_gap_; }
  float width(std::string_view utf8) const;

  struct Quad {
    float x0, y0, x1, y1;  // pixels, y down
    float s0, t0, s1, t1;  // atlas texture coordinates
  };
  // Quads for `utf8` with its baseline starting at (x, y); returns the pen position after it.
  float layout(std::string_view utf8, float x, float y, std::vector<Quad>& out) const;

  int atlas_width() const { return atlas_width_; }
  int atlas_height() const { return atlas_height_; }
  const std::vector<std::uint8_t>& atlas() const { return atlas_; }  // one byte of coverage

 private:
  struct Glyphs;
  std::unique_ptr<Glyphs> glyphs_;
  float pixel_height_, ascent_ = 0, descent_ = 0, line_gap_ = 0;
  int atlas_width_ = 0, atlas_height_ = 0;
  std::vector<std::uint8_t> atlas_;
};

// Decodes one code point and advances `i`; malformed bytes give U+FFFD.
char32_t next_code_point(std::string_view s, std::size_t& i);

}  // namespace apiclab::render
