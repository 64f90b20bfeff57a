// The performance ledger's rows: what this machine and build are, and appending without rewriting.
#include "app/perf_ledger.hpp"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <regex>
#include <sstream>

#include "app/cli.hpp"
#include "app/run_outputs.hpp"

#ifndef APICLAB_BUILD_FLAVOUR
#define APICLAB_BUILD_FLAVOUR "unknown"
#endif

namespace apiclab::cli {

const char* const kLedgerHeader =
    "date,commit,cpu,isa,build,method,scene,dim,precision,threads,scheme,kernel,integrator,"
    "particles,steps,particle_steps_per_s,wall_s,sim_s_per_wall_s,note";

namespace {

// The value of the first /proc/cpuinfo line whose key is `key` ("" if none).
std::string cpuinfo_value(const std::string& key) {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    const auto colon = line.find(':');
    if (colon == std::string::npos || line.compare(0, key.size(), key) != 0) continue;
    if (line.find_first_not_of(" \t", key.size()) != colon) continue;
    const auto start = line.find_first_not_of(' ', colon + 1);
    return start == std::string::npos ? "" : line.substr(start);
  }
  return "";
}

// AMD's core generation from the CPU family and model (model names such as "AMD EPYC" omit it).
std::string amd_generation(int family, int model) {
  if (family == 26) return "Zen 5";
  if (family == 25) {
    const bool zen4 = (model >= 0x10 && model <= 0x1f) || (model >= 0x60 && model <= 0x7f) ||
                      (model >= 0xa0 && model <= 0xaf);
    return zen4 ? "Zen 4" : "Zen 3";
  }
  if (family == 23) return model >= 0x30 ? "Zen 2" : "Zen";
  return "";
}

// `git describe --always --dirty --tags` as the version string carries it ("" without git).
std::string git_describe() {
  const std::string v = apiclab_version();
  const auto at = v.find("(git ");
  if (at == std::string::npos) return "";
  return v.substr(at + 5, v.find(')', at) - at - 5);
}

std::string cell(const std::optional<double>& v, const char* format) {
  if (!v) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, *v);
  return buf;
}

std::string cell(long v) { return v > 0 ? std::to_string(v) : ""; }

// The row's own note, then the machine's load (1-minute average) and an uncommitted tree.
std::string full_note(const std::string& note) {
  std::string out = note;
  double load[1];
  if (getloadavg(load, 1) == 1) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "load %.2f", load[0]);
    out += (out.empty() ? "" : "; ") + std::string(buf);
  }
  if (git_describe().ends_with("-dirty")) out += "; uncommitted changes";
  return out;
}

}  // namespace

std::string ledger_date() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &utc);
  return buf;
}

std::string ledger_commit() {
  static const std::regex hash(R"(^(?:.*-g)?([0-9a-f]{7,40})(?:-dirty)?$)");
  std::smatch m;
  const std::string describe = git_describe();
  return std::regex_match(describe, m, hash) ? m[1].str() : "";
}

std::string ledger_cpu() {
  std::string name =
      std::regex_replace(cpuinfo_value("model name"), std::regex(R"(\((R|TM)\))"), "");
  name = std::regex_replace(name, std::regex(R"(\s+)"), " ");
  if (name.empty()) return "unknown";
  if (cpuinfo_value("vendor_id") == "AuthenticAMD" && name.find("Zen") == std::string::npos) {
    const std::string gen = amd_generation(std::atoi(cpuinfo_value("cpu family").c_str()),
                                           std::atoi(cpuinfo_value("model").c_str()));
    if (!gen.empty()) name += " " + gen;
  }
  return name;
}

std::string ledger_isa() {
#if defined(__AVX512F__)
  return "avx512";
#elif defined(__AVX2__)
  return "avx2";
#elif defined(__AVX__)
  return "avx";
#elif defined(__SSE4_2__)
  return "sse4.2";
#elif defined(__SSE2__)
  return "sse2";
#elif defined(__ARM_FEATURE_SVE)
  return "sve";
#elif defined(__aarch64__)
  return "neon";
#else
  return "unknown";
#endif
}

std::string ledger_build() { return APICLAB_BUILD_FLAVOUR; }

std::string ledger_line(const LedgerRow& r) {
  const std::vector<std::string> cells = {ledger_date(),
                                          ledger_commit(),
                                          ledger_cpu(),
                                          ledger_isa(),
                                          r.build.empty() ? ledger_build() : r.build,
                                          r.method,
                                          r.scene,
                                          cell(r.dim),
                                          r.precision,
                                          cell(r.threads),
                                          r.scheme,
                                          r.kernel,
                                          r.integrator,
                                          cell(r.particles),
                                          cell(r.steps),
                                          cell(r.rate, "%.0f"),
                                          cell(r.wall, "%.4g"),
                                          cell(r.sim_rate, "%.4g"),
                                          full_note(r.note)};
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    std::string c = cells[i];
    for (char& ch : c)
      if (ch == ',' || ch == '\n') ch = ch == ',' ? ';' : ' ';
    line += (i ? "," : "") + c;
  }
  return line;
}

void check_ledger(const std::string& path) {
  std::ifstream in(path);
  std::string first;
  if (!in || !std::getline(in, first) || first.empty()) return;  // absent or empty: a new ledger
  if (!first.empty() && first.back() == '\r') first.pop_back();
  if (first != kLedgerHeader)
    throw UsageError("--record: " + path +
                     " is not a performance ledger (its first line is not the ledger's header)");
}

void append_ledger_rows(const std::string& path, const std::vector<LedgerRow>& rows) {
  check_ledger(path);
  std::ifstream probe(path, std::ios::ate);
  const bool fresh = !probe || probe.tellg() <= 0;
  char last = '\n';
  if (!fresh) probe.seekg(-1, std::ios::end), probe.get(last);
  probe.close();
  std::ostringstream text;
  if (fresh) text << kLedgerHeader << '\n';
  if (last != '\n') text << '\n';  // a last row without its newline stays a row of its own
  for (const auto& r : rows) text << ledger_line(r) << '\n';
  std::ofstream out(path, std::ios::app);
  out << text.str();
  out.flush();
  if (!out) throw UsageError("--record: cannot append to " + path);
}

}  // namespace apiclab::cli
