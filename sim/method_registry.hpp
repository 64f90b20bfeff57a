// Solver methods by the scene's `solver.method` key (the idea of Nori's NORI_REGISTER_CLASS):
// each method registers a constructor, which dispatches on dimension and precision itself, and
// a validate hook the scene reader calls on the method's own keys of the `solver` section.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"

namespace apiclab {

class Simulation;

struct SolverMethod {
  std::string name;  // the `solver.method` value
  std::string help;
  std::function<std::unique_ptr<Simulation>(const SceneDesc&, Precision)> make;
  // Reads the method's word and switch keys of the scene's `solver` section into scene.solver and
  // checks how the values combine (its numbers, the registry's keys naming the method, are read
  // before); throws SceneError with one line naming the file and key.
  std::function<void(SceneSection&, SceneDesc&)> validate;
};

// Adds a method; a second method of the same name replaces nothing and throws std::logic_error.
// The methods built into apiclab_sim are listed in method_registry.cpp (a static library drops
// a self-registering object file that nothing references), each defined next to its solver.
void register_method(SolverMethod method);
// The method of that name, or nullptr.
const SolverMethod* find_method(const std::string& name);
// All registered method names, sorted, for error messages and help.
std::vector<std::string> method_names();

// Why an MPM scheme cannot run with the rest of these solver settings ("" when it can): MLS-MPM
// needs the quadratic or cubic kernel and symplectic Euler, PolyPIC the quadratic kernel. The
// scene reader and compare's panes check it.
std::string scheme_conflict(const SolverDesc& solver);

// The built-in methods, each defined with its solver.
SolverMethod mpm_method();       // sim/mpm/mpm_method.cpp
SolverMethod eol_method();       // sim/eol/eol_method.cpp
SolverMethod eulerian_method();  // sim/eol/eol_method.cpp

}  // namespace apiclab
