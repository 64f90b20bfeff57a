// Definitions of EolSimulation<T, D>, one stage per file; included by the explicit
// instantiations sim/eol/eol_{2d,3d}.cpp only.
#pragma once
#include "sim/eol/contact/eol_contact.hpp"
#include "sim/eol/contact/implicit_contact.hpp"
#include "sim/eol/eol_checkpoint.hpp"
#include "sim/eol/eol_forces.hpp"
#include "sim/eol/eol_ledger.hpp"
#include "sim/eol/eol_mass.hpp"
#include "sim/eol/eol_measure.hpp"
#include "sim/eol/eol_plasticity.hpp"
#include "sim/eol/eol_setup.hpp"
#include "sim/eol/eol_snapshot.hpp"
#include "sim/eol/eol_step.hpp"
#include "sim/eol/eol_time_step.hpp"
#include "sim/eol/surface/eol_surfaces.hpp"
