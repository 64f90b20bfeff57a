// Definitions of MpmSimulation<T, D>, one concept per file; included by the explicit
// instantiations sim/mpm_{2d,3d}_{float,double}.cpp only.
#pragma once
#include "g2p.hpp"
#include "grid_update.hpp"
#include "implicit.hpp"
#include "mpm_measure.hpp"
#include "mpm_output.hpp"
#include "mpm_setup.hpp"
#include "mpm_step.hpp"
#include "p2g.hpp"
#include "time_step_rules.hpp"
#include "transfer_schemes.hpp"
#include "transfer_xpic.hpp"
