// The headers nearly every test file includes, compiled once for all the test binaries
// (tests/CMakeLists.txt: target_precompile_headers): GoogleTest, Eigen, JSON and the solver's
// public headers. A test file still includes what it uses.
#pragma once
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "sim/mpm/mpm.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"
