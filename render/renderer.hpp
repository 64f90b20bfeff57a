// Draws immutable Snapshots into whatever OpenGL 3.3 core context is current (an offscreen
// one for `apiclab render` and the tests, the GUI's window): particles as discs (2D) or sphere
// impostors (3D), velocity arrows, domain box, colliders, grid lines, and a pixel-space
// overlay (panels, lines, text) drawn over everything at end_frame().
#pragma once
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "render/camera.hpp"
#include "render/color.hpp"
#include "render/math.hpp"
#include "render/snapshot_stats.hpp"
#include "render/text.hpp"
#include "sim/geometry/collider_body.hpp"
#include "sim/snapshot.hpp"

namespace apiclab::render {

class Program;

struct Rect {
  float x = 0, y = 0, w = 0, h = 0;  // pixels, origin at the top left
};

// How one scene is drawn, every value resolved (auto_scale.hpp picks the automatic ones).
struct SceneStyle {
  ColorMode color = ColorMode::speed;
  float color_max = 1;  // speed or noise at the top of the colormap
  bool vectors = false;
  bool surface = true, surface_vectors = false;  // object surfaces (EoL), arrows on them
  float vector_scale = 0.1f;                     // world length of an arrow per unit of speed
  int vector_every = 1;  // one arrow per this many particles, picked by a hash of the id
  bool box = true, colliders = true, grid = false;
  float particle_scale = 1;  // multiplies each particle's drawing radius
  float line_px = 1;         // width of thin lines, pixels
  std::string grid_field;    // grid layers: the node field to colour by (empty: each one's first)
};

// The color of particle i in `style`'s mode.
Rgba8 particle_color(const Snapshot& s, std::size_t i, const SceneStyle& style);
// Whether particle `id` carries an arrow when one in `every` does (steady across frames).
bool carries_arrow(std::size_t id, int every);

class Renderer {
 public:
  Renderer();  // compiles the shaders: needs a current context with gl:: loaded
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Starts a frame of width x height pixels in the bound framebuffer; clears it.
  void begin_frame(int width, int height, Rgba8 background = {255, 255, 255, 255});
  // The scene inside `rect`, through `camera` (made with the rect's aspect).
  void draw_scene(const Snapshot& s, const Camera& camera, Rect rect, const SceneStyle& style);

  // Overlay, in pixels; drawn over the scenes by end_frame: fills, then lines, then text.
  void fill_rect(Rect r, Rgba8 color);
  void fill_quad(const Vec2 corners[4], const Rgba8 colors[4]);         // corners in fan order
  void line(Vec2 a, Vec2 b, float width, Rgba8 color, float head = 0);  // head > 0: arrow
  // Text with its baseline at y; align 0 left, 0.5 centre, 1 right. Returns its width.
  float text(std::string_view utf8, float x, float y, float size, Rgba8 color, float align = 0);
  float text_width(std::string_view utf8, float size);
  const Font& font(float size);
  void end_frame();

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  struct ParticleInstance {
    Vec3 center;
    float radius;
    Rgba8 color;
  };
  struct SegmentInstance {
    Vec3 from, to;
    Rgba8 color;
    float width, head, lift;
  };
  struct FillVertex {
    Vec3 position;
    Rgba8 color;
  };
  struct TextVertex {
    float x, y, u, v;
    Rgba8 color;
  };
  struct FontEntry {
    std::unique_ptr<Font> font;
    unsigned texture = 0;
    std::vector<TextVertex> vertices;
  };

  // Fills and uploads the particle buffer; returns whether point sprites can draw it.
  bool upload_particles(const Snapshot& s, const Camera& camera, Rect rect,
                        const SceneStyle& style);
  void draw_particles(const Program& program, const Camera& camera, Rect rect, bool points);
  // Scene geometry into scene_lines_ / scene_fills_.
  void add_grid(const Box3& box, float dx, int axis_a, int axis_b, float line_px);
  void add_box(const Box3& box, int dim, float line_px);
  // A collider where it is at `time` (sim/geometry/collider_body.hpp).
  void add_collider(const ColliderDesc& c, double time, const Box3& box, int dim, float line_px,
                    float pixels_per_unit);
  void add_body(const ColliderPose& body, int dim, float line_px);
  // The snapshot's grid layers into scene_lines_ / scene_fills_ (render/grid_layers.cpp).
  void add_grid_layers(const Snapshot& s, const Camera& camera, float line_px,
                       float pixels_per_unit, const std::string& field);
  // The snapshot's surfaces (render/surface_layers.cpp): lines (2D), shaded triangles (3D).
  void add_surface_layers(const Snapshot& s, const Camera& camera, float line_px);
  void draw_arrows(const Snapshot& s, const Camera& camera, Vec2 viewport, const SceneStyle& style);
  // The floor of a 3D domain (the face at the minimum of axis `up`) with contact shadows.
  void draw_floor(const Box3& box, int up, const Mat4& view_projection, Rect rect);
  void draw_segments(const std::vector<SegmentInstance>& segments, const Mat4& view,
                     const Mat4& projection, Vec2 viewport);
  void draw_fills(const std::vector<FillVertex>& vertices, const Mat4& matrix);
  void set_viewport(Rect r);
  FontEntry& font_entry(float size);

  int width_ = 0, height_ = 0;
  std::unique_ptr<Program> discs_, spheres_, shadow_map_, floor_, segments_, fills_, text_;
  unsigned shadow_fbo_ = 0, shadow_texture_ = 0;
  float largest_radius_ = 0;
  unsigned quad_vbo_ = 0, template_vbo_ = 0;
  unsigned particle_vao_[2] = {0, 0}, particle_vbo_ = 0;  // [1]: points
  float max_point_size_ = 1;
  unsigned segment_vao_ = 0, segment_vbo_ = 0;
  unsigned fill_vao_ = 0, fill_vbo_ = 0;
  unsigned text_vao_ = 0, text_vbo_ = 0;
  std::vector<ParticleInstance> particles_;
  std::vector<SegmentInstance> scene_lines_;
  std::vector<FillVertex> scene_fills_;
  std::vector<SegmentInstance> overlay_lines_;
  std::vector<FillVertex> overlay_fills_;
  std::map<int, FontEntry> fonts_;  // by size in pixels
};

}  // namespace apiclab::render
