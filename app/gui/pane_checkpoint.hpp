// The viewer's checkpoints (docs/viewer.md, "Checkpoints"): a pane saved as the checkpoint of a
// `run` (DIR/checkpoint.bin with DIR/diagnostics.csv, the rows the run would have written), so
// `apiclab run --resume DIR` continues it headless; and a run's checkpoint opened as a pane,
// paused where the run stood, which the viewer continues or saves again.
#pragma once
#include <cstddef>
#include <string>

#include "app/gui/viewer_state.hpp"
#include "sim/measure/run_summary.hpp"

namespace apiclab::gui {

// The run a pane was opened from: its diagnostics up to the checkpoint and its running summary,
// so that the pane saved again is the same run continued.
struct PaneOrigin {
  std::string csv_text;  // the run's CSV up to the checkpoint, header included
  RunSummary summary;
  long unconverged = 0;
};

// The folder `Save` writes into when none is typed: apiclab-out/SCENE.checkpoint.
std::string default_checkpoint_dir(const ViewerState& st);

// Queues a checkpoint of every pane: one pane into DIR, several into DIR/pane-1, DIR/pane-2, ...
// The worker writes them between two steps; Published::notice or ::error says how it went.
void save_pane_checkpoints(const ViewerState& st, SimWorker& worker, const std::string& dir);

// Opens DIR's checkpoint as the only pane, paused where the run stood. A checkpoint that cannot
// be opened leaves the panes as they were and says why in st.load_error.
void open_checkpoint(ViewerState& st, SimWorker& worker, const std::string& dir);

}  // namespace apiclab::gui
