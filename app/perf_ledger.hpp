// The performance ledger (docs/data/performance-ledger.csv, docs/performance.md): one CSV row per
// measurement, appended by `apiclab bench --record FILE`, never rewritten.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace apiclab::cli {

// The ledger's header line (its 19 columns, in order).
extern const char* const kLedgerHeader;

// One measurement. Empty strings and empty optionals are empty cells; the date, commit, CPU, ISA
// and (unless set) build flavour are this machine's and this binary's.
struct LedgerRow {
  std::string build;  // empty: this binary's flavour (native, x86-64-v3, ...); or "reference"
  std::string method = "mpm", scene = "bench", precision, scheme, kernel, integrator, note;
  int dim = 0, threads = 0;
  long particles = 0, steps = 0;               // 0: empty cell
  std::optional<double> rate, wall, sim_rate;  // particle-steps/s, s, simulated s per wall s
};

// What this binary and machine put in every row: the date (UTC), the commit of `git describe`,
// the CPU model (/proc/cpuinfo), the ISA the build targets and its flavour (-march).
std::string ledger_date();
std::string ledger_commit();
std::string ledger_cpu();
std::string ledger_isa();
std::string ledger_build();

// Throws UsageError unless `path` is absent, empty, or starts with the ledger's header.
void check_ledger(const std::string& path);
// Appends `rows` to `path` (the header first when it is absent or empty), one line each.
void append_ledger_rows(const std::string& path, const std::vector<LedgerRow>& rows);
// One row as its CSV line (no newline); commas inside a cell become semicolons.
std::string ledger_line(const LedgerRow& row);

}  // namespace apiclab::cli
