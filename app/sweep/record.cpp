#include "app/sweep/record.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "app/frame_loop.hpp"
#include "app/particle_export.hpp"
#include "app/run_outputs.hpp"
#include "sim/eol/eol_positions.hpp"
#include "sim/measure/run_summary.hpp"

namespace apiclab::sweep {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
// ASF1: positions as 32-bit floats (older records); ASF2: at the run's precision.
constexpr char kMagic[4] = {'A', 'S', 'F', '2'};
constexpr char kFloatMagic[4] = {'A', 'S', 'F', '1'};

double json_number(const json& j, const char* key) {
  if (!j.contains(key) || j[key].is_null()) return std::numeric_limits<double>::quiet_NaN();
  return j[key].get<double>();
}

// frames.bin: magic, dim, scalar bytes (4: float run, 8: double run), count, object[count], then
// per frame t, kinetic, elastic and positions[count·dim] at the run's precision.
class FrameWriter {
 public:
  FrameWriter(const std::string& path, Precision precision)
      : out_(path, std::ios::binary), bytes_(precision == Precision::single ? 4 : 8) {
    if (!out_) throw std::runtime_error("cannot write " + path);
  }
  void add(const Snapshot& s, const std::vector<double>& positions, const DiagnosticsRow& row) {
    if (!header_written_) {
      const std::int32_t dim = s.dim;
      const std::uint64_t n = s.count();
      out_.write(kMagic, 4);
      out_.write(reinterpret_cast<const char*>(&dim), sizeof dim);
      out_.write(reinterpret_cast<const char*>(&bytes_), sizeof bytes_);
      out_.write(reinterpret_cast<const char*>(&n), sizeof n);
      out_.write(reinterpret_cast<const char*>(s.object.data()),
                 std::streamsize(s.object.size() * sizeof(std::int32_t)));
      header_written_ = true;
    }
    const double head[3] = {s.time, row.kinetic, row.elastic};
    out_.write(reinterpret_cast<const char*>(head), sizeof head);
    if (bytes_ == 8) {
      out_.write(reinterpret_cast<const char*>(positions.data()),
                 std::streamsize(positions.size() * sizeof(double)));
    } else {
      const std::vector<float> x(positions.begin(), positions.end());
      out_.write(reinterpret_cast<const char*>(x.data()),
                 std::streamsize(x.size() * sizeof(float)));
    }
  }

 private:
  std::ofstream out_;
  std::int32_t bytes_;
  bool header_written_ = false;
};

// The frame's points at the run's precision, by particle id: an MPM run's particle table (its
// scalar widened), an EoL run's nodes; another family's as its snapshot holds them.
std::vector<double> positions_of(const Simulation& sim, const Snapshot& snap) {
  if (const TransferControls* t = sim.transfers()) {
    const ParticleTable table = t->particle_table();
    if (const ParticleColumn* x = table.find("position")) return x->values;
  }
  if (auto x = eol_node_positions(sim)) return *x;
  return {snap.positions.begin(), snap.positions.end()};
}

double rms(const std::vector<float>& v, int components) {
  if (v.empty()) return 0;
  double s = 0;
  for (float x : v) s += double(x) * double(x);
  return std::sqrt(s / double(v.size() / std::size_t(components)));
}

json conservation_json(const metrics::Conservation& c) {
  return {{"max_energy", c.max_energy},
          {"final_energy", c.final_energy},
          {"max_angular", c.max_angular},
          {"final_angular", c.final_angular},
          {"angular_relative", c.angular_relative},
          {"max_momentum", c.max_momentum},
          {"final_momentum", c.final_momentum}};
}

}  // namespace

int record_run(const cli::RunOptions& o, const std::string& dir) {
  SceneDesc scene = cli::load_scene_with_options(o);
  const Precision precision = cli::precision_of(o);
  cli::apply_threads(o.threads);
  const double start = now_seconds();
  const fs::path final_dir(dir);
  const fs::path tmp = final_dir.string() + ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp, ec);
  if (ec) throw cli::UsageError("--record: cannot create '" + tmp.string() + "'");
  std::ofstream csv(tmp / "diagnostics.csv");
  csv << diagnostics_header() << '\n';
  auto sim = make_simulation(scene, precision);
  FrameWriter frames((tmp / "frames.bin").string(), sim->precision());
  // --dump NAME with --record: the dumps go inside the record (so they appear with it, whole).
  std::unique_ptr<ParticleDump> dump;
  if (!o.dump.empty()) {
    if (o.dump.find('/') != std::string::npos || o.dump == "." || o.dump == "..")
      throw cli::UsageError("--dump with --record names a folder inside the record, not a path: '" +
                            o.dump + "'");
    const std::vector<DumpFormat> formats = cli::dump_formats_of(o, sim->transfers());
    if (!sim->transfers() && formats_need_particles(formats))
      throw cli::UsageError("--dump: solver method '" + scene.solver.method + "' " +
                            dump_without_particles);
    fs::create_directories(tmp / o.dump, ec);
    if (ec) throw cli::UsageError("--record: cannot create '" + (tmp / o.dump).string() + "'");
    dump = std::make_unique<ParticleDump>((tmp / o.dump).string(), formats);
  }
  FrameIndex dump_frames;  // dump/frames.csv: each frame's real time, as run --dump writes
  if (dump) dump_frames = FrameIndex((tmp / o.dump).string());
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  write_diagnostics_row(csv, first);
  std::vector<DiagnosticsRow> rows = {first};
  rows.reserve(4096);
  RunRecord rec;
  rec.particles = long(particle_count(*sim));
  Lockstep panes({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& r) {
    write_diagnostics_row(csv, r);
    rows.push_back(r);
    rec.step_wall_s += r.wall_seconds;
    rec.newton_iters += r.newton_iters;
    rec.cg_iters += r.cg_iters;
    if (!r.converged) ++rec.unconverged_steps;
  };
  double rms_speed0 = 0;
  const TransferControls* transfers = sim->transfers();
  run_frame_loop(FrameTimes(scene, o.max_steps), panes, on_row, [&](int f) {
    if (sim->failure()) return false;
    auto snap = sim->snapshot();
    frames.add(*snap, positions_of(*sim, *snap), rows.back());
    if (dump) {
      dump->write(*sim, f);
      dump_frames.add(f, sim->time(), {sim->steps()});
    }
    ++rec.frames;
    const double speed = rms(snap->velocities, snap->dim);
    if (f == 0) rms_speed0 = speed;
    if (transfers) {
      transfers->fill_velocity_noise(*snap);
      const double scale = std::max({rms_speed0, speed, 1e-300});
      rec.noise = std::max(rec.noise, rms(snap->noise, 1) / scale);
    }
    return true;
  });
  csv.close();
  rec.steps = sim->steps();
  if (const auto& failure = sim->failure()) {
    rec.blew_up = true;
    rec.fail_step = failure->step;
    rec.fail_t = failure->t;
    rec.fail_quantity = failure->quantity;
    rec.fail_message = failure->message;
  }
  rec.conservation =
      metrics::conservation(rows, sim->total_mass(), DriftRule::domain_extent(scene));
  rusage use{};
  getrusage(RUSAGE_SELF, &use);
  rec.cpu_s = double(use.ru_utime.tv_sec + use.ru_stime.tv_sec) +
              1e-6 * double(use.ru_utime.tv_usec + use.ru_stime.tv_usec);
  rec.peak_rss_mb = double(use.ru_maxrss) / 1024.0;
  rec.total_wall_s = now_seconds() - start;
  json j = {{"id", final_dir.filename().string()},
            {"scene", scene.name},
            {"overrides", o.sets},
            {"precision", o.precision},
            {"threads", o.threads},
            {"particles", rec.particles},
            {"steps", rec.steps},
            {"frames", rec.frames},
            {"step_wall_s", rec.step_wall_s},
            {"total_wall_s", rec.total_wall_s},
            {"cpu_s", rec.cpu_s},
            {"peak_rss_mb", rec.peak_rss_mb},
            {"newton_iters", rec.newton_iters},
            {"cg_iters", rec.cg_iters},
            {"unconverged_steps", rec.unconverged_steps},
            {"outcome", rec.blew_up ? "blew_up" : "completed"},
            {"noise", rec.noise},
            {"conservation", conservation_json(rec.conservation)}};
  if (rec.blew_up)
    j["failure"] = {{"step", rec.fail_step},
                    {"t", rec.fail_t},
                    {"quantity", rec.fail_quantity},
                    {"message", rec.fail_message}};
  {
    std::ofstream out(tmp / "result.json");
    out << j.dump(1) << '\n';
    if (!out) throw cli::UsageError("--record: cannot write " + (tmp / "result.json").string());
  }
  fs::remove_all(final_dir, ec);
  fs::rename(tmp, final_dir, ec);
  if (ec) throw cli::UsageError("--record: cannot rename into '" + dir + "': " + ec.message());
  if (!o.quiet)
    std::fprintf(stderr, "apiclab: %s: %s in %ld steps, %.3g s; recorded in %s\n",
                 scene.name.c_str(), rec.blew_up ? rec.fail_message.c_str() : "completed",
                 rec.steps, rec.step_wall_s, dir.c_str());
  return 0;
}

bool record_complete(const std::string& dir) {
  return fs::is_regular_file(fs::path(dir) / "result.json");
}

void write_refusal(const std::string& dir, int exit_status, const std::string& cause) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  std::ofstream(fs::path(dir) / "refused.txt")
      << "exit " << exit_status << (cause.empty() ? "" : ": " + cause) << '\n';
}

std::string read_refusal(const std::string& dir) {
  std::ifstream in(fs::path(dir) / "refused.txt");
  std::string line;
  std::getline(in, line);
  return line;
}

RunRecord read_record(const std::string& dir) {
  const fs::path path = fs::path(dir) / "result.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  json j = json::parse(in, nullptr, false);
  if (j.is_discarded()) throw std::runtime_error(path.string() + ": malformed JSON");
  RunRecord r;
  r.id = j.value("id", "");
  r.particles = j.value("particles", 0L);
  r.steps = j.value("steps", 0L);
  r.frames = j.value("frames", 0L);
  r.step_wall_s = json_number(j, "step_wall_s");
  r.total_wall_s = json_number(j, "total_wall_s");
  r.cpu_s = json_number(j, "cpu_s");
  r.peak_rss_mb = json_number(j, "peak_rss_mb");
  r.newton_iters = json_number(j, "newton_iters");
  r.cg_iters = json_number(j, "cg_iters");
  r.unconverged_steps = j.value("unconverged_steps", 0L);
  r.blew_up = j.value("outcome", "") == "blew_up";
  r.noise = json_number(j, "noise");
  if (r.blew_up && j.contains("failure")) {
    const json& f = j["failure"];
    r.fail_step = f.value("step", 0L);
    r.fail_t = json_number(f, "t");
    r.fail_quantity = f.value("quantity", "");
    r.fail_message = f.value("message", "");
  }
  const json& c = j["conservation"];
  r.conservation = {json_number(c, "max_energy"),      json_number(c, "final_energy"),
                    json_number(c, "max_angular"),     json_number(c, "final_angular"),
                    c.value("angular_relative", true), json_number(c, "max_momentum"),
                    json_number(c, "final_momentum")};
  return r;
}

metrics::RunFrames read_frames(const std::string& dir) {
  const fs::path path = fs::path(dir) / "frames.bin";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  char magic[4];
  std::int32_t dim = 0, bytes = 0;
  std::uint64_t n = 0;
  metrics::RunFrames run;
  if (!in.read(magic, 4)) return run;  // no frame at all (failed before frame 0)
  if (std::string(magic, 4) == std::string(kFloatMagic, 4))
    throw OldFramesError(path.string() +
                         ": recorded by an older apiclab with positions as 32-bit floats, which "
                         "would put a floor of about 1e-7 under its errors");
  if (std::string(magic, 4) != std::string(kMagic, 4))
    throw std::runtime_error(path.string() + ": not a frames file");
  in.read(reinterpret_cast<char*>(&dim), sizeof dim);
  in.read(reinterpret_cast<char*>(&bytes), sizeof bytes);
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!in || (dim != 2 && dim != 3) || (bytes != 4 && bytes != 8))
    throw std::runtime_error(path.string() + ": not a frames file");
  run.dim = dim;
  run.object.resize(n);
  in.read(reinterpret_cast<char*>(run.object.data()), std::streamsize(n * sizeof(std::int32_t)));
  const std::size_t values = n * std::uint64_t(dim);
  std::vector<char> raw(values * std::size_t(bytes));
  for (;;) {
    double head[3];
    if (!in.read(reinterpret_cast<char*>(head), sizeof head)) break;
    if (!in.read(raw.data(), std::streamsize(raw.size())))
      throw std::runtime_error(path.string() + ": truncated frame");
    metrics::Frame f{head[0], head[1], head[2], std::vector<double>(values)};
    if (bytes == 8) {
      std::memcpy(f.positions.data(), raw.data(), raw.size());
    } else {
      const auto* x = reinterpret_cast<const float*>(raw.data());
      std::copy(x, x + values, f.positions.begin());
    }
    run.frames.push_back(std::move(f));
  }
  return run;
}

bool frames_current(const std::string& dir) {
  std::ifstream in(fs::path(dir) / "frames.bin", std::ios::binary);
  char magic[4];
  return !in.read(magic, 4) || std::string(magic, 4) != std::string(kFloatMagic, 4);
}

}  // namespace apiclab::sweep
