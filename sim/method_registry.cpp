#include "sim/method_registry.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace apiclab {
namespace {

std::map<std::string, SolverMethod>& methods() {
  static std::map<std::string, SolverMethod> table = [] {
    std::map<std::string, SolverMethod> t;
    for (SolverMethod m : {mpm_method(), eol_method(), eulerian_method()})
      t.emplace(m.name, std::move(m));
    return t;
  }();
  return table;
}

}  // namespace

void register_method(SolverMethod method) {
  auto& table = methods();
  if (table.count(method.name))
    throw std::logic_error("solver method '" + method.name + "' registered twice");
  std::string name = method.name;
  table.emplace(std::move(name), std::move(method));
}

const SolverMethod* find_method(const std::string& name) {
  auto& table = methods();
  auto it = table.find(name);
  return it == table.end() ? nullptr : &it->second;
}

std::vector<std::string> method_names() {
  std::vector<std::string> names;
  for (const auto& [name, method] : methods()) names.push_back(name);
  return names;  // std::map keeps them sorted
}

}  // namespace apiclab
