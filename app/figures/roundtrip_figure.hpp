// Fig 11 (Sec 6.8): the round-trip transfer error of PIC and APIC against Δx, log-log, with
// least-squares slopes; DIR/fig11_roundtrip.png and .csv.
#pragma once
#include <string>
#include <vector>

#include "app/figures/chart_canvas.hpp"

namespace apiclab::figures {

void write_roundtrip_figure(ChartCanvas& canvas, const std::vector<int>& resolutions, int threads,
                            const std::string& dir);

}  // namespace apiclab::figures
