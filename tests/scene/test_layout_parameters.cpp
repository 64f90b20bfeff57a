// The layout table (sim/scene/layout_parameters.hpp): every key of a shape, a sampling, an
// object's motion and anchors and a collider is read from the file and by --set alike, listed in
// docs/scene-keys.md, refused out of range with its one message, and defaults as the table says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sim/geometry/collider_body.hpp"
#include "sim/scene/layout_parameters.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {
namespace {

using nlohmann::json;

// Scenes that between them give every layout key explicitly.
const std::vector<std::string> kLayoutScenes = {
    R"({"dim": 2, "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.05},
        "materials": [{"E": 1000, "nu": 0.3, "rho": 2}, {"E": 2000, "nu": 0.3, "rho": 2}],
        "objects": [{"shape": {"type": "ball", "center": [0.5, 0.5], "radius": 0.2,
                               "rotation": {"axis": [0, 0, 1], "degrees": 30}},
                     "material": 0, "sampling": {"type": "ppc", "ppc": 4},
                     "velocity": [0.1, 0], "angular_velocity": 0.5}],
        "colliders": [{"type": "plane", "point": [0, 0.1], "normal": [0, 1],
                       "velocity": [0, 0.5]}]})",
    R"({"dim": 2, "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.05},
        "materials": [{"E": 1000, "nu": 0.3, "rho": 2}],
        "objects": [{"shape": {"type": "box", "min": [0.3, 0.3], "max": [0.7, 0.7],
                               "rotation": {"axis": [0, 0, 1], "random_seed": 7}},
                     "material": 0, "sampling": {"type": "poisson", "radius": 0.05, "seed": 3}}],
        "colliders": [{"type": "box", "center": [0.5, 0.1], "size": [0.4, 0.1], "degrees": 10,
                       "angular_velocity": 0.5}]})",
    R"({"dim": 2, "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.05},
        "materials": [{"E": 1000, "nu": 0.3, "rho": 2}],
        "objects": [{"shape": {"type": "ball", "center": [0.5, 0.5], "radius": 0.2},
                     "material": 0}],
        "colliders": [{"type": "rod", "center": [0.5, 0.1], "radius": 0.02, "length": 0.3,
                       "path": [[0, 0.5, 0.1], [1, 0.6, 0.2, 30]]}]})",
    R"({"dim": 2, "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.05},
        "materials": [{"E": 1000, "nu": 0.3, "rho": 2}],
        "objects": [{"shape": {"type": "box", "min": [0.3, 0.3], "max": [0.7, 0.7]},
                     "material": 0, "sampling": {"type": "triangulated", "spacing": 0.05},
                     "anchors": {"rows": ["top"], "stiffness": 1000}}]})",
    R"({"dim": 3, "domain": {"min": [0, 0, 0], "max": [1, 1, 1], "dx": 0.05},
        "materials": [{"E": 1000, "nu": 0.3, "rho": 2}],
        "objects": [{"shape": {"type": "annulus", "center": [0.5, 0.5, 0.5], "inner": 0.1,
                               "outer": 0.2, "axis": [0, 0, 1], "length": 0.2},
                     "material": 0, "sampling": {"type": "lattice", "spacing": 0.05},
                     "angular_velocity": [0, 0, 1]}],
        "colliders": [{"type": "box", "center": [0.5, 0.1, 0.5], "axis": [0, 1, 0]}]})",
    R"({"dim": 3, "domain": {"min": [0, 0, 0], "max": [1, 1, 1], "dx": 0.05},
        "materials": [{"E": 1000, "nu": 0.3, "rho": 2}],
        "objects": [{"shape": {"type": "mesh", "file": "meshes/bunny.obj", "scale": 0.5,
                               "translate": [0.5, 0.5, 0.5]}, "material": 0}]})"};

json::json_pointer layout_pointer(const std::string& key) {
  std::string p = "/" + key;
  for (char& c : p)
    if (c == '.') c = '/';
  return json::json_pointer(p);
}

// The first layout scene that gives the key at index 0.
json layout_scene_for(const LayoutParameter& p) {
  for (const std::string& text : kLayoutScenes) {
    json j = json::parse(text);
    if (j.contains(layout_pointer(p.key_at(0)))) return j;
  }
  ADD_FAILURE() << "no layout scene gives " << p.key;
  return json::parse(kLayoutScenes[0]);
}

// A value as the file writes it.
json file_value(const LayoutParameter& p, const LayoutValue& v, int dim) {
  switch (p.form) {
    case LayoutForm::count:
    case LayoutForm::material:
    case LayoutForm::seed:
      return p.form == LayoutForm::seed ? v.seed : static_cast<long long>(v.x[0]);
    case LayoutForm::number:
      return v.x[0];
    case LayoutForm::spin:
      if (dim == 2) return v.x[2];
      return json{v.x[0], v.x[1], v.x[2]};
    case LayoutForm::axis:
      return json{v.x[0], v.x[1], v.x[2]};
    case LayoutForm::keys: {
      json keys = json::array();
      for (const ColliderKey& k : v.keys) {
        json row = {k.t};
        for (int i = 0; i < dim; ++i) row.push_back(k.point[size_t(i)]);
        row.push_back(k.degrees);
        keys.push_back(row);
      }
      return keys;
    }
    case LayoutForm::point:
      break;
  }
  json a = json::array();
  for (int i = 0; i < dim; ++i) a.push_back(v.x[size_t(i)]);
  return a;
}

// A valid value that differs from `v` (a point moved by 0.01, a length 10 % longer).
LayoutValue another_layout_value(const LayoutParameter& p, LayoutValue v) {
  if (p.form == LayoutForm::seed) {
    ++v.seed;
  } else if (p.form == LayoutForm::count || p.form == LayoutForm::material) {
    v.x[0] += 1;
  } else if (p.form == LayoutForm::number) {
    v.x[0] = p.range.lo == 0 ? 1.1 * v.x[0] : v.x[0] + 3;
  } else if (p.form == LayoutForm::keys) {
    for (ColliderKey& k : v.keys) k.point[0] += 0.01, k.degrees += 1;
  } else {
    for (double& x : v.x) x += 0.01;
  }
  return v;
}

// A value the table refuses, or none (every real allowed, any direction).
std::optional<LayoutValue> bad_layout_value(const LayoutParameter& p) {
  if (p.direction) return LayoutValue{};
  if (!std::isfinite(p.range.lo)) return std::nullopt;
  const double step = p.form == LayoutForm::number ? 1e-3 : 1;
  return LayoutValue{{p.range.lo - step, p.range.lo - step, p.range.lo - step},
                     std::int64_t(p.range.lo - step)};
}

std::string layout_message(const std::string& text, const std::vector<std::string>& overrides) {
  try {
    parse_scene_text(text, "good.json", overrides);
    return "accepted";
  } catch (const SceneError& e) {
    return e.what();
  }
}

bool same_layout_value(const LayoutValue& a, const LayoutValue& b) {
  auto same_key = [](const ColliderKey& p, const ColliderKey& q) {
    return p.t == q.t && p.point == q.point && p.degrees == q.degrees;
  };
  return a.x == b.x && a.seed == b.seed &&
         std::equal(a.keys.begin(), a.keys.end(), b.keys.begin(), b.keys.end(), same_key);
}

TEST(LayoutParameters, EveryKeyIsReadListedDefaultedAndRefusedAlike) {
  std::ifstream table_file(std::string(APICLAB_SOURCE_DIR) + "/docs/scene-keys.md");
  const std::string table((std::istreambuf_iterator<char>(table_file)),
                          std::istreambuf_iterator<char>());
  int refused = 0;
  for (const LayoutParameter& p : layout_parameters()) {
    const std::string key = p.key_at(0);
    SCOPED_TRACE(key);
    EXPECT_NE(table.find("| `" + std::string(p.key) + "` |"), std::string::npos) << "not listed";
    int index = -1;
    EXPECT_EQ(find_layout(p.key_at(2), &index), &p);
    EXPECT_EQ(index, p.key.find('*') == std::string_view::npos ? 0 : 2);
    const json scene = layout_scene_for(p);
    const std::string text = scene.dump();
    const SceneDesc base = parse_scene_text(text, "good.json");
    // Read from the file and by --set alike (the dimension changes every vector: not here).
    if (key != "dim") {
      const json value = file_value(p, another_layout_value(p, p.get(base, 0)), base.dim);
      json edited = scene;
      edited[layout_pointer(key)] = value;
      const SceneDesc file = parse_scene_text(edited.dump(), "good.json");
      const SceneDesc set = parse_scene_text(text, "good.json", {key + "=" + value.dump()});
      EXPECT_TRUE(same_layout_value(p.get(file, 0), p.get(set, 0))) << "the file and --set differ";
      EXPECT_FALSE(same_layout_value(p.get(file, 0), p.get(base, 0)))
          << value.dump() << " was not read";
    }
    // Refused with the one message, from the file and by --set.
    if (const auto bad = bad_layout_value(p)) {
      ++refused;
      const json value = file_value(p, *bad, base.dim);
      const std::string expected =
          "good.json: key '" + key + "': " +
          (p.form == LayoutForm::seed       ? "expected a non-negative integer, got " + value.dump()
           : p.form == LayoutForm::material ? "no material with index " + value.dump()
                                            : *layout_problem(p, *bad, base.dim));
      json edited = scene;
      edited[layout_pointer(key)] = value;
      EXPECT_EQ(layout_message(edited.dump(), {}), expected) << "the file";
      EXPECT_EQ(layout_message(text, {key + "=" + value.dump()}), expected) << "--set";
    }
    // Left out: refused when required, else the table's default, as in a scene built in code.
    json left_out = scene;
    left_out[layout_pointer(key).parent_pointer()].erase(layout_pointer(key).back());
    if (p.required) {
      EXPECT_EQ(layout_message(left_out.dump(), {}),
                "good.json: key '" + key + "': required key is missing");
      continue;
    }
    if (!p.unset_default.empty()) continue;
    const LayoutValue fallback{p.default_value, std::int64_t(p.default_value[0])};
    const LayoutValue read = p.get(parse_scene_text(left_out.dump(), "good.json"), 0);
    SceneDesc code;
    code.objects.emplace_back();
    code.colliders.emplace_back();
    const LayoutValue built = p.get(code, 0);
    if (p.form == LayoutForm::seed) {
      EXPECT_EQ(read.seed, fallback.seed);
      EXPECT_EQ(built.seed, fallback.seed) << "built in code";
    } else {
      EXPECT_EQ(read.x, fallback.x);
      EXPECT_EQ(built.x, fallback.x) << "built in code";
    }
  }
  EXPECT_GE(refused, 16);
}

// A collider scene of dimension 2 with one collider given as JSON.
std::string collider_scene(const std::string& collider) {
  return R"({"dim": 2, "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.05},
             "materials": [{"E": 1000, "nu": 0.3, "rho": 2}],
             "objects": [{"shape": {"type": "ball", "center": [0.5, 0.5], "radius": 0.2},
                          "material": 0}],
             "colliders": [)" +
         collider + "]}";
}

// A keyed path: at each key's time the body is at the key's point and turn; between keys its
// velocity and spin are the keys' slopes; before the first and after the last it holds still.
TEST(ColliderBody, KeyedPathIsAtItsKeysWithTheirSlopes) {
  const SceneDesc s = parse_scene_text(collider_scene(R"({"type": "box", "size": [0.2, 0.1],
                         "path": [[0, 0.2, 0.1], [0.5, 0.4, 0.3, 90], [1.5, 0.4, 0.5, 45]]})"),
                                       "good.json");
  const ColliderDesc& c = s.colliders.at(0);
  const double pi = std::acos(-1.0);
  for (const ColliderKey& k : c.path) {
    const ColliderPose p = collider_pose(c, 2, k.t);
    EXPECT_NEAR(p.center[0], k.point[0], 1e-15);
    EXPECT_NEAR(p.center[1], k.point[1], 1e-15);
    EXPECT_NEAR(std::atan2(p.axes[0][1], p.axes[0][0]), k.degrees * pi / 180, 1e-14);
  }
  const ColliderPose first = collider_pose(c, 2, 0.25), second = collider_pose(c, 2, 1.0);
  EXPECT_NEAR(first.velocity[0], 0.2 / 0.5, 1e-14);
  EXPECT_NEAR(first.velocity[1], 0.2 / 0.5, 1e-14);
  EXPECT_NEAR(first.spin[2], 0.5 * pi / 0.5, 1e-14);
  EXPECT_NEAR(second.velocity[0], 0.0, 1e-14);
  EXPECT_NEAR(second.velocity[1], 0.2, 1e-14);
  EXPECT_NEAR(second.spin[2], -0.25 * pi, 1e-14);
  // The slope is the path's rate: a central difference of the pose at 1.0 s.
  const double h = 1e-6;
  const ColliderPose a = collider_pose(c, 2, 1.0 - h), b = collider_pose(c, 2, 1.0 + h);
  EXPECT_NEAR((b.center[1] - a.center[1]) / (2 * h), second.velocity[1], 1e-8);
  // A point of the body moves with ν + ω × r.
  const Vec3d corner{0.45, 0.45, 0};
  const Vec3d v = second.velocity_at(corner);
  EXPECT_NEAR(v[0], -second.spin[2] * (corner[1] - second.center[1]), 1e-14);
  for (double t : {-1.0, 2.0}) {
    const ColliderPose held = collider_pose(c, 2, t);
    EXPECT_EQ(held.velocity, (Vec3d{0, 0, 0}));
    EXPECT_EQ(held.spin, (Vec3d{0, 0, 0}));
  }
  EXPECT_NEAR(collider_pose(c, 2, 2.0).center[1], 0.5, 1e-15);
}

// Box and rod distances: inside negative, the outward normal, and a spinning body turned.
TEST(ColliderBody, BoxAndRodDistances) {
  const SceneDesc s =
      parse_scene_text(collider_scene(R"({"type": "box", "center": [0.5, 0.2], "size": [0.4, 0.2],
                         "angular_velocity": 1.5707963267948966},
                        {"type": "rod", "center": [0.5, 0.8], "length": 0.4, "radius": 0.05,
                         "degrees": 90})"),
                       "good.json");
  const ColliderPose box = collider_pose(s.colliders[0], 2, 0);
  EXPECT_NEAR(box.distance({0.5, 0.35, 0}).phi, 0.05, 1e-15);
  EXPECT_NEAR(box.distance({0.5, 0.25, 0}).phi, -0.05, 1e-15);
  EXPECT_NEAR(box.distance({0.5, 0.25, 0}).normal[1], 1, 1e-15);
  const ColliderPose turned = collider_pose(s.colliders[0], 2, 1);  // a quarter turn
  EXPECT_NEAR(turned.distance({0.5, 0.45, 0}).phi, 0.05, 1e-14);
  const ColliderPose rod = collider_pose(s.colliders[1], 2, 0);  // upright
  EXPECT_NEAR(rod.distance({0.5, 1.1, 0}).phi, 0.05, 1e-14);
  EXPECT_NEAR(rod.distance({0.6, 0.85, 0}).phi, 0.05, 1e-14);
  EXPECT_NEAR(rod.distance({0.6, 0.85, 0}).normal[0], 1, 1e-14);
}

// A bad path gets one message naming the key.
TEST(ColliderBody, BadPathsAreRefused) {
  const auto message = [](const std::string& collider) {
    return layout_message(collider_scene(collider), {});
  };
  EXPECT_EQ(message(R"({"type": "rod", "path": [[0, 0.5, 0.5], [0, 0.6, 0.5]]})"),
            "good.json: key 'colliders.0.path': path key 1 is at t = 0, not after the key "
            "before it (t = 0)");
  EXPECT_EQ(message(R"({"type": "rod", "path": [[0, 0.5]]})"),
            "good.json: key 'colliders.0.path': key 0: expected [t, x, y] or [t, x, y, degrees], "
            "got [0,0.5]");
  EXPECT_EQ(message(R"({"type": "rod", "path": []})"),
            "good.json: key 'colliders.0.path': expected at least one key");
  EXPECT_EQ(message(R"({"type": "box", "path": [[0, 0.5, 0.5]], "velocity": [1, 0]})"),
            "good.json: key 'colliders.0.path': give a path or velocity and angular_velocity, "
            "not both");
  EXPECT_EQ(message(R"({"type": "box", "center": [0.5, 0.5], "size": [0.1, 0]})"),
            "good.json: key 'colliders.0.size': collider box size 0 is outside the allowed range "
            "(0, inf)");
  EXPECT_EQ(message(R"({"type": "box", "size": [0.1, 0.1]})"),
            "good.json: key 'colliders.0.center': required key is missing");
  EXPECT_EQ(
      message(R"({"type": "cone", "center": [0.5, 0.5]})"),
      "good.json: key 'colliders.0.type': unknown collider type 'cone' (expected plane|box|rod)");
}

}  // namespace
}  // namespace apiclab
