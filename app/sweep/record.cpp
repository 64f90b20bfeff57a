#include "app/sweep/record.hpp"

#include <omp.h>
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
#include <optional>
#include <stdexcept>

#include "app/checkpoint.hpp"
#include "app/frame_loop.hpp"
#include "app/output_file.hpp"
#include "app/output_owner.hpp"
#include "app/particle_export.hpp"
#include "app/run_outputs.hpp"
#include "sim/eol/eol_positions.hpp"
#include "sim/measure/run_summary.hpp"
#include "sim/state_io.hpp"

namespace apiclab::sweep {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
// ASF1: positions as 32-bit floats (older records); ASF2: at the run's precision.
constexpr char kFramesMagic[4] = {'A', 'S', 'F', '2'};
constexpr char kFloatMagic[4] = {'A', 'S', 'F', '1'};

double json_number(const json& j, const char* key) {
  if (!j.contains(key) || j[key].is_null()) return std::numeric_limits<double>::quiet_NaN();
  return j[key].get<double>();
}

// frames.bin: magic, dim, scalar bytes (4: float run, 8: double run), count, object[count], then
// per frame t, kinetic, elastic and positions[count·dim] at the run's precision.
class FrameWriter {
 public:
  // keep > 0: a resumed record, whose file goes on after its first `keep` bytes.
  FrameWriter(const std::string& path, Precision precision, std::uint64_t keep = 0)
      : bytes_(precision == Precision::single ? 4 : 8), size_(keep), header_written_(keep > 0) {
    std::error_code ec;
    if (keep > 0) fs::resize_file(path, keep, ec);
    out_.open(path, keep > 0 ? std::ios::binary | std::ios::app : std::ios::binary);
    if (!out_ || ec) throw std::runtime_error("cannot write " + path);
  }
  std::uint64_t size() const { return size_; }
  void flush() { out_.flush(); }
  // The frame's points; every frame has the points of the first (a fixed set of material points).
  void add(int dim, double t, const MaterialPoints& points, const DiagnosticsRow& row) {
    const std::vector<double>& positions = points.positions;
    const std::vector<std::int32_t>& object = points.object;
    if (!header_written_) {
      const std::int32_t d = dim;
      const std::uint64_t n = object.size();
      out_.write(kFramesMagic, 4);
      out_.write(reinterpret_cast<const char*>(&d), sizeof d);
      out_.write(reinterpret_cast<const char*>(&bytes_), sizeof bytes_);
      out_.write(reinterpret_cast<const char*>(&n), sizeof n);
      out_.write(reinterpret_cast<const char*>(object.data()),
                 std::streamsize(object.size() * sizeof(std::int32_t)));
      header_written_ = true;
      size_ += 4 + sizeof d + sizeof bytes_ + sizeof n + object.size() * sizeof(std::int32_t);
    }
    if (count_ == 0) count_ = positions.size();
    if (positions.size() != count_)  // a reader could not tell the frames apart
      throw std::logic_error("frames.bin: a frame of " + std::to_string(positions.size()) +
                             " values after frames of " + std::to_string(count_));
    size_ += sizeof(double) * 3 + positions.size() * std::size_t(bytes_);
    const double head[3] = {t, row.kinetic, row.elastic};
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
  std::uint64_t size_ = 0;  // bytes written
  std::size_t count_ = 0;   // values per frame, the first frame's
  bool header_written_ = false;
};

// The frame's points at the run's precision with their objects: an MPM run's particles by id
// (its particle table's positions, the scalar widened), an EoL run's surface vertices
// (sim/eol/eol_positions.hpp); another family's as its snapshot holds them.
MaterialPoints points_of(const Simulation& sim, const Snapshot& snap) {
  if (const TransferControls* t = sim.transfers()) {
    const ParticleTable table = t->particle_table();
    if (const ParticleColumn* x = table.find("position")) return {x->values, snap.object};
  }
  if (auto p = eol_surface_points(sim)) return std::move(*p);
  return {{snap.positions.begin(), snap.positions.end()}, snap.object};
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
          {"final_momentum", c.final_momentum},
          {"energy_relative", c.energy_relative}};
}

// The row's fields in a fixed order, for a record's checkpoint.
void save_row(StateWriter& w, const DiagnosticsRow& r) {
  for (double v : {r.t, r.dt, r.kinetic, r.kinetic_grid, r.potential, r.elastic, r.total, r.p[0],
                   r.p[1], r.p[2], r.L[0], r.L[1], r.L[2], r.wall_seconds, r.newton_iters,
                   r.cg_iters, r.residual, r.grid_nodes, r.grid_bytes})
    w.value(v);
  w.value(std::int64_t(r.step));
  w.value(std::uint8_t(r.converged));
  w.text(r.dt_limit);
}

DiagnosticsRow load_row(StateReader& in) {
  DiagnosticsRow r;
  for (double* v : {&r.t, &r.dt, &r.kinetic, &r.kinetic_grid, &r.potential, &r.elastic, &r.total,
                    &r.p[0], &r.p[1], &r.p[2], &r.L[0], &r.L[1], &r.L[2], &r.wall_seconds,
                    &r.newton_iters, &r.cg_iters, &r.residual, &r.grid_nodes, &r.grid_bytes})
    in.value(*v);
  r.step = long(in.value<std::int64_t>());
  r.converged = in.value<std::uint8_t>() != 0;
  r.dt_limit = in.text();
  return r;
}

// Everything a record run carries from one step to the next besides the solver: where its files
// end, the rows (conservation is measured over all of them) and the record's running sums.
struct RecordProgress {
  std::int32_t last_frame = -1;
  std::uint64_t csv_bytes = 0, frames_bytes = 0, index_bytes = 0;
  double rms_speed0 = 0;
  RunRecord rec;
  std::vector<DiagnosticsRow> rows;
  std::vector<PvdSeries::Entry> series;
};

void save_progress(StateWriter& w, const RecordProgress& p) {
  w.tag("record");
  for (std::uint64_t v : {p.csv_bytes, p.frames_bytes, p.index_bytes}) w.value(v);
  w.value(p.last_frame);
  w.value(p.rms_speed0);
  for (double v : {p.rec.step_wall_s, p.rec.newton_iters, p.rec.cg_iters, p.rec.noise}) w.value(v);
  w.value(std::int64_t(p.rec.frames));
  w.value(std::int64_t(p.rec.unconverged_steps));
  w.value(std::uint64_t(p.rows.size()));
  for (const DiagnosticsRow& r : p.rows) save_row(w, r);
  w.value(std::uint64_t(p.series.size()));
  for (const PvdSeries::Entry& e : p.series) {
    w.value(e.t);
    w.value(std::int32_t(e.part));
    w.text(e.file);
  }
}

RecordProgress load_progress(StateReader& r) {
  RecordProgress p;
  r.tag("record");
  for (std::uint64_t* v : {&p.csv_bytes, &p.frames_bytes, &p.index_bytes}) r.value(*v);
  r.value(p.last_frame);
  r.value(p.rms_speed0);
  for (double* v : {&p.rec.step_wall_s, &p.rec.newton_iters, &p.rec.cg_iters, &p.rec.noise})
    r.value(*v);
  p.rec.frames = long(r.value<std::int64_t>());
  p.rec.unconverged_steps = long(r.value<std::int64_t>());
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) p.rows.push_back(load_row(r));
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) {
    PvdSeries::Entry e;
    e.t = r.value<double>();
    e.part = r.value<std::int32_t>();
    e.file = r.text();
    p.series.push_back(std::move(e));
  }
  if (p.rows.empty()) throw StateError("its record holds no diagnostics row");
  return p;
}

// The files a checkpoint counted are there, at least as long as it counted.
void check_length(const fs::path& path, std::uint64_t bytes) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec || size < bytes)
    throw StateError(path.string() + " is shorter than the checkpoint counted");
}

// The checkpoint of an unfinished record, when one of this run's settings is there and whole:
// its progress, and the solver's state loaded into `sim`. Anything else (none, another build,
// other settings, damage) starts the run from zero, saying why when there was one.
std::optional<RecordProgress> resume_record(const std::string& checkpoint_dir, const fs::path& tmp,
                                            const nlohmann::json& settings, const std::string& dump,
                                            Simulation& sim, bool& sim_touched) {
  if (!fs::exists(cli::checkpoint_path(checkpoint_dir))) return std::nullopt;
  try {
    const cli::CheckpointFile f = cli::read_checkpoint(checkpoint_dir);
    if (const std::string d =
            cli::settings_difference(f.header.value("settings", json()), settings);
        !d.empty())
      throw StateError("it was written with other settings: " + d);
    StateReader state(f.bytes.data() + f.state_at, f.state_size);
    RecordProgress p = load_progress(state);
    check_length(tmp / "diagnostics.csv", p.csv_bytes);
    check_length(tmp / "frames.bin", p.frames_bytes);
    if (!dump.empty()) check_length(tmp / dump / "frames.csv", p.index_bytes);
    sim_touched = true;
    sim.load_state(state);
    std::fprintf(stderr, "apiclab: resuming %s from %s at frame %d (step %ld, t = %g s)\n",
                 f.header.value("record", "").c_str(), checkpoint_dir.c_str(), p.last_frame,
                 f.header.value("step", 0L), f.header.value("t", 0.0));
    return p;
  } catch (const std::exception& e) {  // cli::UsageError, StateError
    std::fprintf(stderr, "apiclab: %s: not resumed (%s); the run starts from zero\n",
                 checkpoint_dir.c_str(), e.what());
    return std::nullopt;
  }
}

// Where a record grows: DIR.tmp-PID (renamed at the end; a killed run leaves nothing to reuse),
// or with checkpoints DIR.partial, which outlives a killed run for the next one to resume.
fs::path work_dir(const fs::path& final_dir, bool checkpoints) {
  return final_dir.string() + (checkpoints ? ".partial" : ".tmp-" + std::to_string(::getpid()));
}

// The checkpoint's header: which record, its settings, and where it stands.
json record_header(const fs::path& final_dir, const json& settings, const Simulation& sim,
                   int last_frame) {
  return {{"record", final_dir.filename().string()},
          {"settings", settings},
          {"threads", omp_get_max_threads()},
          {"frame", last_frame},
          {"step", sim.steps()},
          {"t", sim.time()}};
}

}  // namespace

int record_run(const cli::RunOptions& o, const std::string& dir,
               const cli::CheckpointOptions& checkpoint) {
  SceneDesc scene = cli::load_scene_with_options(o);
  const Precision precision = cli::precision_of(o);
  cli::apply_threads(o.threads);
  const double start = now_seconds();
  const fs::path final_dir(dir);
  const fs::path tmp = work_dir(final_dir, checkpoint.on());
  const std::string checkpoint_dir =
      checkpoint.dir.empty() ? (tmp / "checkpoint").string() : checkpoint.dir;
  if (!o.dump.empty() && (o.dump.find('/') != std::string::npos || o.dump == "." || o.dump == ".."))
    throw cli::UsageError("--dump with --record names a folder inside the record, not a path: '" +
                          o.dump + "'");
  const json settings = run_settings(scene, precision, o.sets);
  auto sim = make_simulation(scene, precision);
  if (checkpoint.on() && !sim->checkpoints())
    throw cli::UsageError("solver method '" + scene.solver.method +
                          "' has no checkpoints (--checkpoint-every, --checkpoint-seconds)");
  bool sim_touched = false;
  std::optional<RecordProgress> resumed;
  if (checkpoint.on())
    resumed = resume_record(checkpoint_dir, tmp, settings, o.dump, *sim, sim_touched);
  if (!resumed && sim_touched) sim = make_simulation(scene, precision);  // a half-loaded state
  RecordProgress p = resumed ? std::move(*resumed) : RecordProgress{};
  std::error_code ec;
  if (!resumed) {
    fs::remove_all(tmp, ec);
    fs::remove(cli::checkpoint_path(checkpoint_dir), ec);
  }
  fs::create_directories(tmp, ec);
  if (ec) throw cli::UsageError("--record: cannot create '" + tmp.string() + "'");
  const std::string csv_path = (tmp / "diagnostics.csv").string();
  RowFile csv = resumed ? RowFile(csv_path, p.csv_bytes) : RowFile(csv_path);
  if (!resumed) csv.write_row(diagnostics_header(scene.solver.ledger) + '\n');
  FrameWriter frames((tmp / "frames.bin").string(), sim->precision(), p.frames_bytes);
  // --dump NAME with --record: the dumps go inside the record (so they appear with it, whole).
  std::unique_ptr<ParticleDump> dump;
  FrameIndex dump_frames;  // dump/frames.csv: each frame's real time, as run --dump writes
  if (!o.dump.empty()) {
    const std::vector<DumpFormat> formats = cli::dump_formats_of(o, sim->transfers());
    if (!sim->transfers() && formats_need_particles(formats))
      throw cli::UsageError("--dump: solver method '" + scene.solver.method + "' " +
                            dump_without_particles);
    fs::create_directories(tmp / o.dump, ec);
    if (ec) throw cli::UsageError("--record: cannot create '" + (tmp / o.dump).string() + "'");
    dump = std::make_unique<ParticleDump>((tmp / o.dump).string(), formats);
    dump->series().restore(p.series);
    dump_frames = resumed ? FrameIndex((tmp / o.dump).string(), p.index_bytes)
                          : FrameIndex((tmp / o.dump).string());
  }
  RunRecord& rec = p.rec;
  std::vector<DiagnosticsRow>& rows = p.rows;
  if (!resumed) {
    DiagnosticsRow first = sim->measure();
    first.dt = 0;
    csv.write_row(diagnostics_row_text(first));
    rows = {first};
  }
  rows.reserve(4096);
  rec.particles = long(particle_count(*sim));
  // The record's state after its last whole row (app/checkpoint.hpp, written whole).
  double last_checkpoint = now_seconds();
  std::optional<cli::CheckpointWriter> writer;  // the file is written while the run goes on
  if (checkpoint.on()) writer.emplace(checkpoint_dir);
  const auto save_checkpoint = [&] {
    frames.flush();
    p.csv_bytes = csv.size();
    p.frames_bytes = frames.size();
    p.index_bytes = dump_frames.size();
    if (dump) p.series = dump->series().entries();
    StateWriter w(writer->state());
    save_progress(w, p);
    sim->save_state(w);
    cli::ensure_writable_dir(checkpoint_dir);
    writer->write(record_header(final_dir, settings, *sim, p.last_frame));
    last_checkpoint = now_seconds();
  };
  Lockstep panes({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& r) {
    csv.write_row(diagnostics_row_text(r));
    rows.push_back(r);
    rec.step_wall_s += r.wall_seconds;
    rec.newton_iters += r.newton_iters;
    rec.cg_iters += r.cg_iters;
    if (!r.converged) ++rec.unconverged_steps;
    if (writer) writer->check();
    const double seconds = checkpoint.every_seconds;
    if (seconds > 0 && !sim->failure() && now_seconds() - last_checkpoint >= seconds)
      save_checkpoint();
  };
  const TransferControls* transfers = sim->transfers();
  const auto on_frame = [&](int f) {
    if (sim->failure()) return false;
    auto snap = sim->snapshot();
    frames.add(snap->dim, snap->time, points_of(*sim, *snap), rows.back());
    if (dump) {
      dump->write(*sim, f);
      dump_frames.add(f, sim->time(), {sim->steps()});
    }
    ++rec.frames;
    const double speed = rms(snap->velocities, snap->dim);
    if (f == 0) p.rms_speed0 = speed;
    if (transfers) {
      transfers->fill_velocity_noise(*snap);
      const double scale = std::max({p.rms_speed0, speed, 1e-300});
      rec.noise = std::max(rec.noise, rms(snap->noise, 1) / scale);
    }
    p.last_frame = f;
    if (checkpoint.every_frames > 0 && f > 0 && f % checkpoint.every_frames == 0) save_checkpoint();
    return true;
  };
  run_frame_loop(FrameTimes(scene, o.max_steps), panes, on_row, on_frame,
                 resumed ? p.last_frame : -1);
  if (writer) writer->finish();
  frames.flush();
  rec.steps = sim->steps();
  if (const auto& failure = sim->failure()) {
    rec.blew_up = true;
    rec.fail_step = failure->step;
    rec.fail_t = failure->t;
    rec.fail_quantity = failure->quantity;
    rec.fail_message = failure->message;
  }
  if (!rows.empty()) rec.conservation = metrics::conservation(rows, DriftRule::of(*sim, rows[0]));
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
  // A finished record keeps no checkpoint: nothing is left to resume.
  fs::remove(cli::checkpoint_path(checkpoint_dir), ec);
  fs::remove(checkpoint_dir, ec);  // when empty
  fs::remove_all(final_dir, ec);
  fs::rename(tmp, final_dir, ec);
  if (ec) throw cli::UsageError("--record: cannot rename into '" + dir + "': " + ec.message());
  fs::remove_all(work_dir(final_dir, true), ec);  // an unfinished one of a run without checkpoints
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
                    json_number(c, "final_momentum"),  c.value("energy_relative", true)};
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
  if (std::string(magic, 4) != std::string(kFramesMagic, 4))
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
