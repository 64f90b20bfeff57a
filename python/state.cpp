// The MPM solver's particle arrays seen from NumPy: views in storage order, and writes through
// MpmProbe so that the next step sorts the particles again and measures the written state.
#include "python/state.hpp"

#include <pybind11/numpy.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "sim/mpm/mpm.hpp"
#include "sim/mpm/probe.hpp"

namespace py = pybind11;

namespace apiclab::python {
namespace {

// fn(sim) with sim the MpmSimulation<T, D> behind `s`; false for another solver family.
template <class Fn>
bool with_mpm(Simulation& s, Fn&& fn) {
  if (auto* m = dynamic_cast<MpmSimulation<double, 2>*>(&s)) return fn(*m), true;
  if (auto* m = dynamic_cast<MpmSimulation<float, 2>*>(&s)) return fn(*m), true;
  if (auto* m = dynamic_cast<MpmSimulation<double, 3>*>(&s)) return fn(*m), true;
  if (auto* m = dynamic_cast<MpmSimulation<float, 3>*>(&s)) return fn(*m), true;
  return false;
}

[[noreturn]] void no_particles(const Simulation& s) {
  throw py::value_error("the " + s.scene().solver.method +
                        " method has no particles (grid() and snapshot() show its state)");
}

// A read-only array over `data` that keeps `owner` (the Python Simulation) alive.
template <class E>
py::array view(const E* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               py::handle owner) {
  py::array a(py::dtype::of<E>(), std::move(shape), std::move(strides), data, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

template <class T, int D>
py::dict views_of(MpmSimulation<T, D>& sim, py::handle owner) {
  const auto& p = MpmProbe<const MpmSimulation<T, D>>(sim).particles();
  const auto n = py::ssize_t(p.size());
  const auto t = py::ssize_t(sizeof(T)), vec = py::ssize_t(sizeof(Vec<T, D>)),
             mat = py::ssize_t(sizeof(Mat<T, D>)), i32 = py::ssize_t(sizeof(std::int32_t));
  py::dict d;
  d["x"] = view(reinterpret_cast<const T*>(p.x.data()), {n, D}, {vec, t}, owner);
  d["v"] = view(reinterpret_cast<const T*>(p.v.data()), {n, D}, {vec, t}, owner);
  // Eigen stores a matrix by columns: entry (i, j) of particle q at q·mat + (i + D j)·t.
  d["F"] = view(reinterpret_cast<const T*>(p.F.data()), {n, D, D}, {mat, t, D * t}, owner);
  d["C"] = view(reinterpret_cast<const T*>(p.C.data()), {n, D, D}, {mat, t, D * t}, owner);
  d["mass"] = view(p.mass.data(), {n}, {t}, owner);
  d["volume"] = view(p.volume0.data(), {n}, {t}, owner);
  d["material"] = view(p.material.data(), {n}, {i32}, owner);
  d["object"] = view(p.object.data(), {n}, {i32}, owner);
  d["id"] = view(p.id.data(), {n}, {i32}, owner);
  return d;
}

std::string shape_text(const py::array& a) {
  std::ostringstream s;
  s << '(';
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s << (k ? ", " : "") << a.shape(k);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

// `value` as a C-ordered array of T with the given shape (after the particle count), or ValueError.
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> checked_array(
    const std::string& name, py::handle value, std::size_t n, std::vector<py::ssize_t> tail) {
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a) throw py::value_error("set_state: " + name + " is not a numeric array");
  std::vector<py::ssize_t> want{py::ssize_t(n)};
  want.insert(want.end(), tail.begin(), tail.end());
  bool ok = a.ndim() == py::ssize_t(want.size());
  for (std::size_t k = 0; ok && k < want.size(); ++k) ok = a.shape(py::ssize_t(k)) == want[k];
  if (!ok) {
    std::ostringstream w;
    w << '(';
    for (std::size_t k = 0; k < want.size(); ++k) w << (k ? ", " : "") << want[k];
    w << (want.size() == 1 ? ",)" : ")");
    throw py::value_error("set_state: " + name + " has shape " + shape_text(a) + ", expected " +
                          w.str() + " (the particles in storage order)");
  }
  const T* v = a.data();
  for (py::ssize_t k = 0; k < a.size(); ++k)
    if (!std::isfinite(double(v[k])))
      throw py::value_error(
          "set_state: " + name + " of the particle at index " +
          std::to_string(k / std::max<py::ssize_t>(1, a.size() / py::ssize_t(n))) +
          " is not finite");
  return a;
}

// Positions the step can take: inside the domain (G2P keeps them there; a periodic axis's max
// is its min again).
template <class T, int D>
void check_inside(const SceneDesc& scene, const T* x, std::size_t n) {
  for (std::size_t q = 0; q < n; ++q)
    for (int a = 0; a < D; ++a) {
      const double lo = scene.domain.min[a], hi = scene.domain.max[a], xa = x[q * D + a];
      if (xa < lo || xa > hi || (scene.domain.periodic(a) && xa >= hi)) {
        std::ostringstream m;
        m << "set_state: x of the particle at index " << q << " is " << xa << " on axis " << a
          << ", outside the domain [" << lo << ", " << hi
          << (scene.domain.periodic(a) ? ") (periodic: wrap it)" : "]");
        throw py::value_error(m.str());
      }
    }
}

template <class T, int D>
void write_into(MpmSimulation<T, D>& sim, const py::dict& arrays) {
  const std::size_t n = MpmProbe<const MpmSimulation<T, D>>(sim).particles().size();
  using Arr = py::array_t<T, py::array::c_style | py::array::forcecast>;
  std::vector<std::pair<std::string, Arr>> checked;
  for (const auto& [key, value] : arrays) {
    const std::string name = py::str(key);
    if (name == "x" || name == "v")
      checked.emplace_back(name, checked_array<T>(name, value, n, {D}));
    else if (name == "F" || name == "C")
      checked.emplace_back(name, checked_array<T>(name, value, n, {D, D}));
    else if (name == "mass" || name == "volume")
      checked.emplace_back(name, checked_array<T>(name, value, n, {}));
    else
      throw py::value_error("set_state: '" + name +
                            "' is not a writable particle array (x, v, F, C, mass, volume)");
    if (name == "x") check_inside<T, D>(sim.scene(), checked.back().second.data(), n);
    if (name == "mass" || name == "volume")
      for (std::size_t q = 0; q < n; ++q)
        if (!(checked.back().second.data()[q] > 0))
          throw py::value_error("set_state: " + name + " of the particle at index " +
                                std::to_string(q) + " is not positive");
  }
  MpmProbe<MpmSimulation<T, D>> probe(sim);
  auto& p = probe.particles();
  bool moved = false;
  for (const auto& [name, a] : checked) {
    const T* v = a.data();
    if (name == "x" || name == "v") {
      auto& out = name == "x" ? p.x : p.v;
      for (std::size_t q = 0; q < n; ++q) out[q] = Eigen::Map<const Vec<T, D>>(v + q * D);
      moved = moved || name == "x";
    } else if (name == "F" || name == "C") {
      auto& out = name == "F" ? p.F : p.C;  // rows of the NumPy array are rows of the matrix
      for (std::size_t q = 0; q < n; ++q)
        out[q] = Eigen::Map<const Eigen::Matrix<T, D, D, Eigen::RowMajor>>(v + q * D * D);
    } else {
      auto& out = name == "mass" ? p.mass : p.volume0;
      std::copy(v, v + n, out.begin());
    }
  }
  probe.particles_written(moved);
}

template <class T, int D>
py::dict grid_of(MpmSimulation<T, D>& sim) {
  const auto& g = MpmProbe<const MpmSimulation<T, D>>(sim).grid();
  std::vector<py::ssize_t> shape, strides;  // [i, j(, k)]: axis 0 fastest, as stored
  py::ssize_t stride = sizeof(T);
  Vec<T, D> origin;
  for (int a = 0; a < D; ++a) {
    shape.push_back(g.extent[a]);
    strides.push_back(stride);
    stride *= g.extent[a];
    origin[a] = g.origin[a] + T(g.lo[a]) * g.dx;
  }
  const std::size_t count = g.region_size();
  py::dict d;
  d["origin"] = py::array(py::dtype::of<T>(), {py::ssize_t(D)}, {}, origin.data());
  d["dx"] = double(g.dx);
  py::array mass(py::dtype::of<T>(), shape, strides);
  if (count && g.mass.size() >= count)
    std::copy(g.mass.begin(), g.mass.begin() + std::ptrdiff_t(count),
              static_cast<T*>(mass.mutable_data()));
  d["mass"] = mass;
  std::vector<py::ssize_t> vshape = shape, vstrides;  // [i, j(, k), component]
  vshape.push_back(D);
  for (py::ssize_t s : strides) vstrides.push_back(s * D);
  vstrides.push_back(py::ssize_t(sizeof(T)));
  for (const char* name : {"velocity", "velocity_new"}) {
    const auto& field = std::string(name) == "velocity" ? g.velocity : g.velocity_new;
    py::array a(py::dtype::of<T>(), vshape, vstrides);
    T* out = static_cast<T*>(a.mutable_data());
    if (count && field.size() >= count)
      for (std::size_t i = 0; i < count; ++i)
        for (int c = 0; c < D; ++c) out[i * D + c] = field[i][c];
    d[name] = a;
  }
  return d;
}

}  // namespace

py::dict particle_views(Simulation& sim, py::handle owner) {
  py::dict d;
  if (!with_mpm(sim, [&](auto& m) { d = views_of(m, owner); })) no_particles(sim);
  return d;
}

void write_particles(Simulation& sim, const py::dict& arrays) {
  if (!with_mpm(sim, [&](auto& m) { write_into(m, arrays); })) no_particles(sim);
}

std::string partition_conflict(Simulation& sim) {
  std::string why;
  with_mpm(sim, [&](auto& m) {
    why = MpmProbe<const std::remove_reference_t<decltype(m)>>(m).partition_conflict();
  });
  return why;
}

py::dict mpm_grid(Simulation& sim) {
  py::dict d;
  with_mpm(sim, [&](auto& m) { d = grid_of(m); });
  return d;
}

}  // namespace apiclab::python
