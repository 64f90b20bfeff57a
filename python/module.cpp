// `import apiclab` (docs/python.md): a scene loaded through the same registries as `apiclab run`,
// stepped on the same frame times with the GIL released, its state as NumPy arrays
// (python/state.cpp), its diagnostics as the CSV's columns, its picture through the headless
// renderer. Errors are Python exceptions: SceneError is ValueError, a blow-up SimulationFailed.
#include <omp.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app/assets.hpp"
#include "app/frame_loop.hpp"
#include "app/version.hpp"
#include "python/state.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/registry.hpp"
#include "sim/simulation.hpp"
#ifdef APICLAB_HAVE_RENDER
#include "render/context.hpp"
#include "render/figure.hpp"
#include "render/snapshot_stats.hpp"
#include "render/target.hpp"
#endif

namespace py = pybind11;

namespace apiclab::python {
namespace {

PyObject* g_simulation_failed = nullptr;  // apiclab.SimulationFailed

// One Python Simulation: the solver, the rows of every step taken, and whether a step runs.
struct PySimulation {
  std::unique_ptr<Simulation> sim;
  std::vector<DiagnosticsRow> rows;
  bool busy = false;
};

// Holds `busy` for one call: a second thread calling in while a step runs gets an error, not a
// race.
class BusyGuard {
 public:
  explicit BusyGuard(PySimulation& s) : s_(s) {
    if (s_.busy) throw std::runtime_error("this Simulation is stepping in another thread");
    s_.busy = true;
  }
  ~BusyGuard() { s_.busy = false; }
  BusyGuard(const BusyGuard&) = delete;
  BusyGuard& operator=(const BusyGuard&) = delete;

 private:
  PySimulation& s_;
};

// Reads of the state while another thread steps it would race: refused like a second step.
const PySimulation& idle(const PySimulation& s) {
  if (s.busy) throw std::runtime_error("this Simulation is stepping in another thread");
  return s;
}

// A `--set` value as text: strings as they are, numbers and switches as JSON, others by json.dumps.
std::string set_value(py::handle v) {
  if (py::isinstance<py::str>(v)) return py::str(v);
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) return py::str(py::repr(v));
  return py::str(py::module_::import("json").attr("dumps")(v));
}

// `set`: None, "KEY=VALUE", a list of them, or a dict {KEY: VALUE}.
std::vector<std::string> set_list(py::handle set) {
  std::vector<std::string> out;
  if (set.is_none()) return out;
  if (py::isinstance<py::str>(set)) return {py::str(set)};
  if (py::isinstance<py::dict>(set)) {
    for (const auto& [k, v] : py::reinterpret_borrow<py::dict>(set))
      out.push_back(std::string(py::str(k)) + "=" + set_value(v));
    return out;
  }
  for (py::handle item : set) out.push_back(py::str(item));
  return out;
}

// The scene as `apiclab run` reads it: a path, a shipped name, or a dict of the scene's JSON.
SceneDesc load(py::handle scene, const std::vector<std::string>& sets) {
  SceneDesc s;
  if (py::isinstance<py::dict>(scene)) {
    const std::string text = py::str(py::module_::import("json").attr("dumps")(scene));
    s = parse_scene_text(text, "scene dict", sets);
  } else {
    const std::string arg = py::str(py::module_::import("os").attr("fspath")(scene));
    const std::string path = resolve_scene_path(arg);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
      throw py::value_error("'" + arg +
                            "': no such scene file or shipped scene (apiclab.scenes() lists the "
                            "shipped ones)");
    s = load_scene(path, sets);
  }
  s.asset_dirs.push_back(assets_directory());
  return s;
}

Precision precision_named(const std::string& name, const SceneDesc& scene) {
  if (name != "double" && name != "float")
    throw py::value_error("precision '" + name + "': expected double or float");
  if (name == "float" && scene.solver.method != "mpm")
    throw py::value_error("precision float: the " + scene.solver.method +
                          " solver runs in double precision only");
  return name == "float" ? Precision::single : Precision::dbl;
}

// The next frame time after the simulation's time, as `apiclab run`'s frame loop steps to it:
// f/fps, and time.end for the last frame; past time.end the frames go on at f/fps.
double next_frame_time(const Simulation& s) {
  const FrameTimes times(s.scene());
  const double t = s.time();
  long f = std::max(1L, long(std::floor(t * times.fps)));
  while (f > 1 && double(f - 1) / times.fps > t) --f;
  while (double(f) / times.fps <= t) ++f;
  if (t < times.end && f >= times.frames) return times.end;
  return double(f) / times.fps;
}

// One step towards t_limit with the GIL released; its row kept. Raises SimulationFailed.
void step_towards(PySimulation& self, double t_limit) {
  BusyGuard busy(self);
  DiagnosticsRow row;
  const long before = self.sim->steps();
  std::optional<Failure> failure;
  {
    py::gil_scoped_release free;
    failure = self.sim->step(t_limit, &row);
  }
  if (self.sim->steps() > before) self.rows.push_back(row);
  if (failure) {
    PyErr_SetString(g_simulation_failed, failure->message.c_str());
    throw py::error_already_set();
  }
}

// Steps to time t (landing on every frame time on the way); Ctrl-C raises between steps.
void advance(PySimulation& self, double t) {
  if (!std::isfinite(t)) throw py::value_error("advance: the time must be finite");
  while (self.sim->time() < t) {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    const long before = self.sim->steps();
    step_towards(self, std::min(next_frame_time(*self.sim), t));
    if (self.sim->steps() == before) break;
  }
}

// The rows as the CSV writes them, parsed back into columns: numbers as float64 arrays, words
// (dt_limit) as lists of str, so every column the CSV has appears under its header's name.
py::dict columns_of(const std::vector<DiagnosticsRow>& rows) {
  std::ostringstream csv;
  for (const DiagnosticsRow& r : rows) write_diagnostics_row(csv, r);
  std::vector<std::string> names;
  {
    // With the conservation ledger's columns where the rows carry them.
    std::istringstream header(diagnostics_header(!rows.empty() && rows.front().ledger));
    for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  }
  std::vector<std::vector<std::string>> cells(names.size());
  std::istringstream in(csv.str());
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::size_t c = 0;
    for (std::string f; c < names.size() && std::getline(fields, f, ','); ++c)
      cells[c].push_back(f);
    for (; c < names.size(); ++c) cells[c].push_back("");
  }
  py::dict out;
  for (std::size_t c = 0; c < names.size(); ++c) {
    std::vector<double> values;
    bool numeric = true;
    for (const std::string& f : cells[c]) {
      char* end = nullptr;
      const double v = std::strtod(f.c_str(), &end);
      numeric = numeric && !f.empty() && end && *end == '\0';
      if (!numeric) break;
      values.push_back(v);
    }
    if (numeric) {
      py::array_t<double> a(py::ssize_t(values.size()));
      std::copy(values.begin(), values.end(), a.mutable_data());
      out[names[c].c_str()] = a;
    } else {
      py::list words;
      for (const std::string& f : cells[c]) words.append(f);
      out[names[c].c_str()] = words;
    }
  }
  return out;
}

#ifdef APICLAB_HAVE_RENDER
// The current state drawn as `apiclab render` draws a frame: an RGBA image, rows top first.
py::array render_image(PySimulation& self, int width, int height, const std::string& color,
                       bool vectors) {
  if (width < 16 || height < 16 || width > 8192 || height > 8192)
    throw py::value_error("snapshot: width and height must be 16 to 8192 pixels");
  render::FigureStyle style;
  try {
    style.color = render::parse_color_mode(color);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("snapshot: ") + e.what());
  }
  const SceneDesc& scene = self.sim->scene();
  style.vectors = vectors;
  style.time_step = 1 / scene.time.fps;
  style.up_axis = render::up_axis_from_gravity(scene.gravity, scene.dim);
  std::shared_ptr<Snapshot> snap;
  {
    BusyGuard busy(self);
    snap = self.sim->snapshot();
    if (style.color == render::ColorMode::noise && self.sim->transfers())
      self.sim->transfers()->fill_velocity_noise(*snap);
  }
  // One context and renderer for the module, made on the first snapshot.
  static std::unique_ptr<render::OffscreenContext> context;
  static std::unique_ptr<render::Renderer> renderer;
  if (!context) {
    try {
      context = render::create_offscreen_context(render::Backend::automatic);
    } catch (const render::ContextError& e) {
      throw std::runtime_error(std::string("snapshot: ") + e.what());
    }
  }
  context->make_current();
  if (!renderer) renderer = std::make_unique<render::Renderer>();
  render::RenderTarget target(width, height);
  render::FigureState state;
  render::draw_figure(*renderer, width, height, {snap.get()}, style, state);
  const render::Image image = target.read();
  py::array_t<std::uint8_t> out({py::ssize_t(height), py::ssize_t(width), py::ssize_t(4)});
  std::copy(image.rgba.begin(), image.rgba.end(), out.mutable_data());
  return out;
}
#endif

// The CSV's first row, as `apiclab run` writes it: the state before any step, dt 0.
DiagnosticsRow first_row(const Simulation& sim) {
  DiagnosticsRow r = sim.measure();
  r.dt = 0;
  return r;
}

std::unique_ptr<PySimulation> make(py::object scene, py::object set, const std::string& precision) {
  const SceneDesc desc = load(scene, set_list(set));
  auto s = std::make_unique<PySimulation>();
  s->sim = make_simulation(desc, precision_named(precision, desc));
  s->rows.push_back(first_row(*s->sim));
  return s;
}

// Switches the transfer scheme from the current state, as the viewer's scheme switch does.
void set_scheme(PySimulation& self, const std::string& key, py::object flip_alpha) {
  TransferControls* t = self.sim->transfers();
  if (!t) throw py::value_error("the " + self.sim->scene().solver.method + " method has no scheme");
  SolverDesc solver = self.sim->scene().solver;
  try {
    solver.scheme = parse_choice(scheme_choices(), key, "scheme");
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  const double alpha = flip_alpha.is_none() ? solver.flip_alpha : flip_alpha.cast<double>();
  if (!(alpha >= 0 && alpha <= 1)) throw py::value_error("flip_alpha must be in [0, 1]");
  if (const std::string why = scheme_conflict(solver); !why.empty()) throw py::value_error(why);
  BusyGuard busy(self);
  t->set_scheme(solver.scheme, alpha);
}

}  // namespace

}  // namespace apiclab::python

PYBIND11_MODULE(_apiclab, m) {
  using namespace apiclab;
  using namespace apiclab::python;
  m.doc() = "apiclab: hybrid particle/grid simulation (docs/python.md)";
  m.attr("__version__") = apiclab_version();
  g_simulation_failed = PyErr_NewException("apiclab.SimulationFailed", PyExc_RuntimeError, nullptr);
  m.attr("SimulationFailed") = py::handle(g_simulation_failed);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SceneError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def("scenes_directory", &scenes_directory, "The folder of the shipped scenes.");
  m.def(
      "set_threads", [](int n) { omp_set_num_threads(std::max(1, n)); }, py::arg("n"),
      "Threads of a step (OpenMP); the result does not depend on it.");

  py::class_<PySimulation>(m, "Simulation", "One simulation of a scene (docs/python.md).")
      .def(py::init(&make), py::arg("scene"), py::arg("set") = py::none(),
           py::arg("precision") = "double",
           "scene: a path, a shipped scene's name or a dict of the scene's JSON; set: --set "
           "overrides as 'KEY=VALUE', a list of them or a dict; precision: double or float.")
      .def_property_readonly("time", [](const PySimulation& s) { return s.sim->time(); })
      .def_property_readonly("steps", [](const PySimulation& s) { return s.sim->steps(); })
      .def_property_readonly("dim", [](const PySimulation& s) { return s.sim->dim(); })
      .def_property_readonly("method",
                             [](const PySimulation& s) { return s.sim->scene().solver.method; })
      .def_property_readonly("scheme",
                             [](const PySimulation& s) -> py::object {
                               if (!s.sim->transfers()) return py::none();
                               return py::str(std::string(key_of(s.sim->scene().solver.scheme)));
                             })
      .def_property_readonly("precision",
                             [](const PySimulation& s) {
                               return s.sim->precision() == Precision::single ? "float" : "double";
                             })
      .def_property_readonly("scene_name",
                             [](const PySimulation& s) { return s.sim->scene().name; })
      .def_property_readonly("end_time",
                             [](const PySimulation& s) { return s.sim->scene().time.end; })
      .def_property_readonly("fps", [](const PySimulation& s) { return s.sim->scene().time.fps; })
      .def_property_readonly("particle_count",
                             [](const PySimulation& s) { return particle_count(*s.sim); })
      .def("next_frame_time", [](const PySimulation& s) { return next_frame_time(*s.sim); })
      .def(
          "step", [](PySimulation& s) { step_towards(s, next_frame_time(*s.sim)); },
          "One step, landing on the next frame time as `apiclab run` does.")
      .def("advance", &advance, py::arg("t"), "Steps to time t; Ctrl-C stops between steps.")
      .def(
          "run_to",
          [](py::object self, double t, py::object callback) {
            PySimulation& s = self.cast<PySimulation&>();
            if (!std::isfinite(t)) throw py::value_error("run_to: the time must be finite");
            while (s.sim->time() < t) {
              advance(s, std::min(next_frame_time(*s.sim), t));
              if (!callback.is_none()) callback(self);
            }
          },
          py::arg("t"), py::arg("callback") = py::none(),
          "Steps to time t frame by frame, calling callback(sim) after each frame.")
      .def_property_readonly(
          "state",
          [](py::object self) {
            idle(self.cast<PySimulation&>());
            py::dict views = particle_views(*self.cast<PySimulation&>().sim, self);
            return py::module_::import("types").attr("SimpleNamespace")(**views);
          },
          "Read-only views of the particle arrays in storage order (valid until the next step).")
      .def(
          "set_state",
          [](PySimulation& s, py::kwargs arrays) {
            BusyGuard busy(s);
            write_particles(*s.sim, arrays);
            // Written before the first step: the first row is the written state, as in a run.
            if (s.sim->steps() == 0 && s.rows.size() == 1) s.rows.front() = first_row(*s.sim);
          },
          "Writes x, v, F, C, mass or volume (storage order) between steps.")
      .def(
          "grid",
          [](PySimulation& s) {
            py::dict g = mpm_grid(*idle(s).sim);
            if (!g.empty()) return py::object(g);
            py::list layers;  // a method with grids of its own: its snapshot's layers
            const std::shared_ptr<const Snapshot> snap = s.sim->snapshot();
            for (const GridLayer& l : snap->grids) {
              py::dict d, fields;
              d["name"] = l.name;
              d["nodes"] = py::make_tuple(l.nodes[0], l.nodes[1], l.nodes[2]);
              d["dx"] = l.dx;
              d["translation"] =
                  py::make_tuple(l.translation[0], l.translation[1], l.translation[2]);
              py::array_t<double> rot({3, 3});
              std::copy(l.rotation.begin(), l.rotation.end(), rot.mutable_data());
              d["rotation"] = rot;
              for (const GridLayer::Field& f : l.fields) {
                // nodes i fastest: indexed [i, j, k]
                py::array_t<float> a(
                    {py::ssize_t(l.nodes[0]), py::ssize_t(l.nodes[1]), py::ssize_t(l.nodes[2])},
                    {py::ssize_t(sizeof(float)), py::ssize_t(sizeof(float)) * l.nodes[0],
                     py::ssize_t(sizeof(float)) * l.nodes[0] * l.nodes[1]});
                std::copy(f.values.begin(), f.values.end(), a.mutable_data());
                fields[f.name.c_str()] = a;
              }
              d["fields"] = fields;
              layers.append(d);
            }
            return py::object(layers);
          },
          "The grid fields: MPM's stored region as a dict, another method's grid layers as a list.")
      .def(
          "_partition_conflict", [](PySimulation& s) { return partition_conflict(*idle(s).sim); },
          "For the tests: what breaks the parallel P2G's block partition now, or ''.")
      .def(
          "diagnostics", [](const PySimulation& s) { return columns_of(s.rows); },
          "Every diagnostics CSV column, by name: the first state's row, then one per step.")
      .def(
          "measure", [](const PySimulation& s) { return columns_of({idle(s).sim->measure()}); },
          "The diagnostics of the current state, as one-row columns.")
      .def("clear_diagnostics", [](PySimulation& s) { s.rows.clear(); })
      .def("set_scheme", &set_scheme, py::arg("scheme"), py::arg("flip_alpha") = py::none(),
           "Switches the transfer scheme from the current state (PIC and FLIP drop C).")
      .def(
          "clone",
          [](const PySimulation& s) {
            auto c = std::make_unique<PySimulation>();
            c->sim = idle(s).sim->clone();
            c->rows = s.rows;
            return c;
          },
          "An independent copy of the simulation and its diagnostics.")
#ifdef APICLAB_HAVE_RENDER
      .def("snapshot", &render_image, py::arg("width") = 480, py::arg("height") = 360,
           py::arg("color") = "speed", py::arg("vectors") = false,
           "The state drawn by the headless renderer as an RGBA uint8 array (height, width, 4).")
#endif
      ;
}
