// What a scene will allocate, estimated before anything is allocated: grid nodes from the
// objects' bounding box and dx (the grid stores only the box the particles reach), particles
// from each shape's volume over the sampling spacing^d, times the bytes the solver keeps per
// node and per particle at the chosen precision and dimension. The run,
// render, compare, gui and bench commands refuse a scene whose estimate exceeds the cap (by
// default the machine's available memory) in well under a second, instead of allocating until
// std::bad_alloc or the OOM killer; a sweep calls check_memory per run.
#pragma once
#include <cstddef>
#include <optional>
#include <string>

#include "sim/scene/scene.hpp"

namespace apiclab {

struct MemoryEstimate {
  double grid_nodes = 0, particles = 0;
  double bytes_per_node = 0, bytes_per_particle = 0;
  double bytes() const { return grid_nodes * bytes_per_node + particles * bytes_per_particle; }
  // "about 37 GB (9.1e8 grid nodes x 144 B + 5e7 particles x 690 B)"
  std::string text() const;
};

MemoryEstimate estimate_memory(const SceneDesc& scene, Precision precision);

// The round-trip probe (sim/mpm/roundtrip.hpp) at `resolution` cells per axis, with the scheme's
// own state (PolyPIC's modes, XPIC's node arrays).
MemoryEstimate estimate_roundtrip_memory(int resolution, Scheme scheme = Scheme::apic,
                                         int xpic_order = 2);

// MemAvailable of /proc/meminfo in bytes; empty where it cannot be read.
std::optional<double> available_memory_bytes();

// The cap that applies: solver.max_memory_gb when set, else the available memory; empty when
// nothing is known.
std::optional<double> memory_cap_bytes(const SceneDesc& scene);

// Throws SceneError (one line: the estimate, the cap and how to lift it) when the estimate
// exceeds `cap_bytes`. `what` names the run in the message (the scene file, or an option).
void check_memory(const MemoryEstimate& estimate, std::optional<double> cap_bytes,
                  const std::string& what);
// The same for a scene, with its own cap.
void check_memory(const SceneDesc& scene, Precision precision);

// "1.5 GB", "820 MB", "12 kB".
std::string format_bytes(double bytes);

}  // namespace apiclab
