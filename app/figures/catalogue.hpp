// The figures `apiclab figures` makes, listed once: their ids (the paper's figure numbers, as
// --only takes them), the time figures' scenes, schemes and quantities, and Fig 1's times.
#pragma once
#include <string>
#include <vector>

#include "app/figures/time_figure.hpp"

namespace apiclab::figures {

// Every figure id in the order they are made: 1, 3, 4, 5, 6, 10, 11.
const std::vector<std::string>& figure_ids();
// Throws UsageError naming the first id of `only` that is not a figure.
void check_figure_ids(const std::vector<std::string>& only);
// Whether `id` is to be made: `only` is empty (all) or lists it.
bool wanted(const std::vector<std::string>& only, const std::string& id);

// Figs 3-6 (Secs 6.1-6.4), the scenes as shipped, and Fig 10 (Sec 6.7, the ringing test),
// without runs.
std::vector<TimeFigure> time_figures();
constexpr const char* kRingingFigureId = "10";
constexpr const char* kRingingFramesId = "1";  // Fig 1: frames of Fig 10's runs
// Fig 1's rows: t = 2/24, 5/24, 40/24 s.
const std::vector<double>& ringing_frame_times();

}  // namespace apiclab::figures
