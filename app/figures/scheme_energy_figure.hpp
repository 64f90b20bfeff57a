// The two-ring energy table: the rings of Jiang et al. 2017, Sec 6.4, collide once
// per transfer scheme in scheme_choices() (so a scheme added later appears without an edit),
// all with symplectic Euler and the elastic time-step rule, and the total energy at one fixed
// time is reported per scheme: DIR/scheme_energy.csv, a bar chart DIR/scheme_energy.png, and the
// same table as Markdown on stderr (docs/transfer-schemes.md's table).
#pragma once
#include <string>

#include "app/figures/chart_canvas.hpp"

namespace apiclab::figures {

inline constexpr const char* kSchemeEnergyId = "scheme-energy";

// quick: the coarse, short version the default tests run (t = 0.005 s instead of 0.01 s).
void write_scheme_energy_figure(ChartCanvas& canvas, bool quick, int threads,
                                const std::string& dir);

}  // namespace apiclab::figures
