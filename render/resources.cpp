#include "render/resources.hpp"

#include <stdexcept>
#include <string>

namespace apiclab::render {

std::string_view resource(std::string_view name) {
  for (const Resource& r : resources())
    if (name == r.name) return {reinterpret_cast<const char*>(r.data), r.size};
  throw std::out_of_range("no embedded resource " + std::string(name));
}

}  // namespace apiclab::render
