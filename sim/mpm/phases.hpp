// Definitions of MpmSimulation<T, D>, one concept per file; included by the explicit
// instantiations sim/mpm/mpm_{2d,3d}_{float,double}.cpp only.
#pragma once
#include "sim/mpm/g2p.hpp"
#include "sim/mpm/grid_update.hpp"
#include "sim/mpm/implicit/implicit.hpp"
#include "sim/mpm/mpm_checkpoint.hpp"
#include "sim/mpm/mpm_ledger.hpp"
#include "sim/mpm/mpm_measure.hpp"
#include "sim/mpm/mpm_output.hpp"
#include "sim/mpm/mpm_plasticity.hpp"
#include "sim/mpm/mpm_setup.hpp"
#include "sim/mpm/mpm_step.hpp"
#include "sim/mpm/p2g.hpp"
#include "sim/mpm/schemes/particle_update.hpp"
#include "sim/mpm/schemes/xpic_passes.hpp"
#include "sim/time_step_rules.hpp"
