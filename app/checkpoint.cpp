#include "app/checkpoint.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <sstream>
#include <string_view>

#include "app/output_file.hpp"
#include "app/perf_ledger.hpp"
#include "app/version.hpp"

namespace apiclab::cli {
namespace {

// The envelope: magic, format version, byte-order mark, header and state lengths, the header
// (JSON), the state, and a checksum of header and state.
constexpr char kMagic[16] = {'a', 'p', 'i', 'c', 'l', 'a', 'b', ' ',
                             'c', 'h', 'e', 'c', 'k', 'p', 't', '\n'};
constexpr std::uint32_t kFormatVersion = 2;
constexpr std::uint32_t kByteOrder = 0x01020304;
constexpr std::size_t kPrefix = sizeof(kMagic) + 4 + 4 + 8 + 8;
// States from this size on are written on a thread of their own (CheckpointWriter).
constexpr std::size_t kStateOnThread = std::size_t(1) << 20;

// A 64-bit checksum over 8-byte words in four independent lanes (a multiply-xorshift mix), so a
// checkpoint of 100 MB is checked in well under a frame's time. Fed in pieces, it is the checksum
// of the pieces joined.
class Checksum {
 public:
  void add(const char* data, std::size_t n) {
    total_ += n;
    if (held_ > 0) {
      const std::size_t take = std::min(n, sizeof(block_) - held_);
      std::memcpy(block_ + held_, data, take);
      held_ += take, data += take, n -= take;
      if (held_ < sizeof(block_)) return;
      mix(block_);
      held_ = 0;
    }
    for (; n >= sizeof(block_); data += sizeof(block_), n -= sizeof(block_)) mix(data);
    std::memcpy(block_, data, n);
    held_ = n;
  }
  std::uint64_t value() const {
    std::uint64_t r = total_;
    for (std::size_t i = 0; i < held_; ++i) r = (r ^ std::uint8_t(block_[i])) * k;
    for (std::uint64_t x : h_) r = ((r ^ x) * k) ^ (r >> 31);
    return r;
  }

 private:
  static constexpr std::uint64_t k = 0x9E3779B97F4A7C15ull;
  void mix(const char* data) {
    for (int l = 0; l < 4; ++l) {
      std::uint64_t w;
      std::memcpy(&w, data + 8 * l, 8);
      h_[l] = (h_[l] ^ w) * k;
      h_[l] ^= h_[l] >> 29;
    }
  }
  std::uint64_t h_[4] = {k, k ^ 1, k ^ 2, k ^ 3};
  char block_[32] = {};
  std::size_t held_ = 0;  // bytes of an unfinished block
  std::uint64_t total_ = 0;
};

std::uint64_t checksum(const char* data, std::size_t n) {
  Checksum c;
  c.add(data, n);
  return c.value();
}

template <class V>
void put(std::string& out, V v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(V));
}
template <class V>
V get(const std::string& in, std::size_t at) {
  V v;
  std::memcpy(&v, in.data() + at, sizeof(V));
  return v;
}

nlohmann::json this_build() {
  return {{"apiclab_version", apiclab_version()},
          {"vector_isa", ledger_isa()},
          {"scalar_bytes", {sizeof(float), sizeof(double), sizeof(long)}}};
}

// A JSON value as the messages print it.
std::string shown(const nlohmann::json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// The file as three pieces, so the state is written where it lies: the prefix and the header,
// the state, the checksum of header and state.
struct Envelope {
  std::string front;
  std::string_view state;
  std::string back;
};

Envelope envelope_of(nlohmann::json header, std::string_view state) {
  header["build"] = this_build();
  const std::string head = header.dump();
  Envelope e{"", state, ""};
  e.front.reserve(kPrefix + head.size());
  e.front.append(kMagic, sizeof(kMagic));
  put(e.front, kFormatVersion);
  put(e.front, kByteOrder);
  put(e.front, std::uint64_t(head.size()));
  put(e.front, std::uint64_t(state.size()));
  e.front += head;
  Checksum sum;
  sum.add(head.data(), head.size());
  sum.add(state.data(), state.size());
  put(e.back, sum.value());
  return e;
}

// A test hook (tests/commands/checkpoint_tests.sh): APICLAB_TEST_KILL_CHECKPOINT=N kills the
// process by SIGKILL in its N-th checkpoint write, once half the bytes are in the temporary file,
// where a kill during the write would leave it.
void killed_mid_write_for_test(const std::string& path, const Envelope& e) {
  static int writes = 0;
  const char* at = std::getenv("APICLAB_TEST_KILL_CHECKPOINT");
  if (at == nullptr || std::atoi(at) != ++writes) return;
  std::ofstream part(temporary_name_of(path), std::ios::binary | std::ios::trunc);
  std::size_t half = (e.front.size() + e.state.size() + e.back.size()) / 2;
  for (std::string_view piece : {std::string_view(e.front), e.state, std::string_view(e.back)}) {
    const std::size_t n = std::min(half, piece.size());
    part.write(piece.data(), std::streamsize(n));
    half -= n;
  }
  part.flush();
  std::raise(SIGKILL);
}

void write_envelope(const std::string& dir, const Envelope& e) {
  const std::string path = checkpoint_path(dir);
  killed_mid_write_for_test(path, e);
  write_file_whole(path, {e.front, e.state, e.back});
}

}  // namespace

std::string checkpoint_path(const std::string& dir) {
  return (std::filesystem::path(dir) / "checkpoint.bin").string();
}

std::string checkpoint_dir_of(const CheckpointOptions& c, const std::string& csv) {
  if (!c.dir.empty()) return c.dir;
  std::filesystem::path p(csv);
  if (p.extension() == ".csv") p.replace_extension();
  return p.string() + ".checkpoint";
}

void write_checkpoint(const std::string& dir, nlohmann::json header, const std::string& state) {
  write_envelope(dir, envelope_of(std::move(header), state));
}

struct CheckpointWriter::Pending {
  std::future<void> write;
};

CheckpointWriter::CheckpointWriter(std::string dir)
    : dir_(std::move(dir)), pending_(std::make_unique<Pending>()) {}

CheckpointWriter::~CheckpointWriter() {
  if (pending_->write.valid()) pending_->write.wait();
}

std::string& CheckpointWriter::state() {
  finish();
  state_.clear();  // keeps its capacity: no fresh pages for the next state
  return state_;
}

void CheckpointWriter::write(nlohmann::json header) {
  finish();
  // A small state is written at once: a thread beside the run's threads would cost more.
  if (state_.size() < kStateOnThread) return write_envelope(dir_, envelope_of(header, state_));
  pending_->write = std::async(std::launch::async, [this, h = std::move(header)]() mutable {
    write_envelope(dir_, envelope_of(std::move(h), state_));
  });
}

void CheckpointWriter::check() {
  std::future<void>& w = pending_->write;
  if (w.valid() && w.wait_for(std::chrono::seconds(0)) == std::future_status::ready) w.get();
}

void CheckpointWriter::finish() {
  if (pending_->write.valid()) pending_->write.get();
}

void save_run_state(StateWriter& w, const RunProgress& p, const RunSummary& summary,
                    const std::vector<PvdSeries::Entry>& series) {
  w.tag("run");
  w.value(p.last_frame);
  w.value(p.csv_bytes);
  w.value(p.frames_bytes);
  w.value(p.unconverged);
  summary.save(w);
  w.value(std::uint64_t(series.size()));
  for (const PvdSeries::Entry& e : series) {
    w.value(e.t);
    w.value(std::int32_t(e.part));
    w.text(e.file);
  }
}

RunProgress load_run_state(StateReader& r, RunSummary& summary,
                           std::vector<PvdSeries::Entry>& series) {
  RunProgress p;
  r.tag("run");
  r.value(p.last_frame);
  r.value(p.csv_bytes);
  r.value(p.frames_bytes);
  r.value(p.unconverged);
  summary.load(r);
  const auto n = r.value<std::uint64_t>();
  if (n > r.left() / (sizeof(double) + sizeof(std::int32_t) + sizeof(std::uint64_t)))
    throw StateError("the state ends early");
  series.resize(std::size_t(n));
  for (PvdSeries::Entry& e : series) {
    e.t = r.value<double>();
    e.part = r.value<std::int32_t>();
    e.file = r.text();
  }
  return p;
}

nlohmann::json run_header(const Simulation& sim, const nlohmann::json& settings,
                          const std::string& csv, const std::string& cwd, int frame,
                          nlohmann::json options) {
  return {{"scene", sim.scene().name},
          {"settings", settings},
          {"csv", csv},
          {"threads", omp_get_max_threads()},
          {"cwd", cwd},
          {"frame", frame},
          {"step", sim.steps()},
          {"t", sim.time()},
          {"options", std::move(options)}};
}

CheckpointFile read_checkpoint(const std::string& dir) {
  const std::string path = checkpoint_path(dir);
  const auto refuse = [&](const std::string& why) {
    return UsageError("checkpoint " + dir + ": " + why);
  };
  std::ifstream in(path, std::ios::binary);
  if (!in) throw refuse("no checkpoint.bin in it (run --checkpoint-every N writes one)");
  CheckpointFile f;
  f.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  const std::string& b = f.bytes;
  if (b.size() < sizeof(kMagic) || std::memcmp(b.data(), kMagic, sizeof(kMagic)) != 0)
    throw refuse("checkpoint.bin is not an apiclab checkpoint");
  if (b.size() < kPrefix) throw refuse("checkpoint.bin is truncated");
  const auto version = get<std::uint32_t>(b, sizeof(kMagic));
  if (version != kFormatVersion)
    throw refuse("checkpoint.bin has format version " + std::to_string(version) +
                 ", this build reads version " + std::to_string(kFormatVersion));
  if (get<std::uint32_t>(b, sizeof(kMagic) + 4) != kByteOrder)
    throw refuse("checkpoint.bin was written on a machine of another byte order");
  const auto head = get<std::uint64_t>(b, sizeof(kMagic) + 8);
  const auto state = get<std::uint64_t>(b, sizeof(kMagic) + 16);
  // Lengths past any file's size are damage, not a file cut short: the checksum names them.
  if (head > (1ull << 48) || state > (1ull << 48))
    throw refuse("checkpoint.bin is corrupt (its lengths are impossible)");
  const std::uint64_t whole = kPrefix + head + state + 8;
  if (b.size() < whole)
    throw refuse("checkpoint.bin is truncated (" + std::to_string(b.size()) + " of " +
                 std::to_string(whole) + " bytes)");
  if (b.size() > whole) throw refuse("checkpoint.bin is corrupt (bytes after its end)");
  if (checksum(b.data() + kPrefix, head + state) != get<std::uint64_t>(b, whole - 8))
    throw refuse("checkpoint.bin is corrupt (its checksum does not match)");
  f.header =
      nlohmann::json::parse(b.begin() + kPrefix, b.begin() + long(kPrefix + head), nullptr, false);
  if (!f.header.is_object()) throw refuse("checkpoint.bin is corrupt (its header is not JSON)");
  const nlohmann::json build = this_build();
  for (const auto& [key, value] : build.items())
    if (f.header["build"][key] != value)
      throw refuse("written by another build (" + key + " " + shown(f.header["build"][key]) +
                   ", this build " + shown(value) + "); resume it with the build that wrote it");
  f.state_at = kPrefix + head;
  f.state_size = state;
  return f;
}

nlohmann::json options_json(const RunOptions& o, const std::string& summary,
                            const CheckpointOptions& c) {
  nlohmann::json j = {{"scene", o.scene},
                      {"scheme", o.scheme},
                      {"kernel", o.kernel},
                      {"integrator", o.integrator},
                      {"precision", o.precision},
                      {"frames", o.frames ? nlohmann::json(*o.frames) : nlohmann::json()},
                      {"csv", o.csv},
                      {"dump", o.dump},
                      {"dump_format", o.dump_format},
                      {"sets", o.sets},
                      {"max_memory", o.max_memory},
                      {"max_steps", o.max_steps},
                      {"max_frames", o.max_frames},
                      {"summary", summary},
                      {"checkpoint_every", c.every_frames},
                      {"checkpoint_seconds", c.every_seconds},
                      {"checkpoint_dir", c.dir}};
  const std::pair<const char*, const std::optional<double>*> numbers[] = {
      {"flip_alpha", &o.flip_alpha},
      {"lambda", &o.lambda},
      {"t_end", &o.t_end},
      {"fps", &o.fps},
      {"dt", &o.dt}};
  for (const auto& [key, value] : numbers)
    j[key] = *value ? nlohmann::json(**value) : nlohmann::json();
  return j;
}

void options_from_json(const nlohmann::json& j, RunOptions& o, std::string& summary,
                       CheckpointOptions& c) {
  try {
    o.scene = j.at("scene").get<std::string>();
    o.scheme = j.at("scheme").get<std::string>();
    o.kernel = j.at("kernel").get<std::string>();
    o.integrator = j.at("integrator").get<std::string>();
    o.precision = j.at("precision").get<std::string>();
    if (!j.at("frames").is_null()) o.frames = j.at("frames").get<int>();
    o.csv = j.at("csv").get<std::string>();
    o.dump = j.at("dump").get<std::string>();
    o.dump_format = j.at("dump_format").get<std::string>();
    o.sets = j.at("sets").get<std::vector<std::string>>();
    o.max_memory = j.at("max_memory").get<std::string>();
    o.max_steps = j.at("max_steps").get<double>();
    o.max_frames = j.at("max_frames").get<double>();
    summary = j.at("summary").get<std::string>();
    c.every_frames = j.at("checkpoint_every").get<int>();
    c.every_seconds = j.at("checkpoint_seconds").get<double>();
    c.dir = j.at("checkpoint_dir").get<std::string>();
    const std::pair<const char*, std::optional<double>*> numbers[] = {{"flip_alpha", &o.flip_alpha},
                                                                      {"lambda", &o.lambda},
                                                                      {"t_end", &o.t_end},
                                                                      {"fps", &o.fps},
                                                                      {"dt", &o.dt}};
    for (const auto& [key, value] : numbers)
      if (!j.at(key).is_null()) *value = j.at(key).get<double>();
  } catch (const nlohmann::json::exception&) {
    throw UsageError("checkpoint: its header does not hold the run's options");
  }
}

}  // namespace apiclab::cli
