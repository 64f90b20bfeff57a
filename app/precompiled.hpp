// The headers nearly every command and library file of app/ includes, compiled once for
// apiclab_app_core, apiclab_sweep and apiclab (app/CMakeLists.txt: target_precompile_headers).
// A file still includes what it uses.
#pragma once
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"
