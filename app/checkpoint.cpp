#include "app/checkpoint.hpp"

#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "app/output_file.hpp"
#include "app/perf_ledger.hpp"
#include "app/version.hpp"

namespace apiclab::cli {
namespace {

// The envelope: magic, format version, byte-order mark, header and state lengths, the header
// (JSON), the state, and a checksum of header and state.
constexpr char kMagic[16] = {'a', 'p', 'i', 'c', 'l', 'a', 'b', ' ',
                             'c', 'h', 'e', 'c', 'k', 'p', 't', '\n'};
constexpr std::uint32_t kFormatVersion = 1;
constexpr std::uint32_t kByteOrder = 0x01020304;
constexpr std::size_t kPrefix = sizeof(kMagic) + 4 + 4 + 8 + 8;

// A 64-bit checksum over 8-byte words in four independent lanes (a multiply-xorshift mix), so a
// checkpoint of 100 MB is checked in well under a frame's time.
std::uint64_t checksum(const char* data, std::size_t n) {
  constexpr std::uint64_t k = 0x9E3779B97F4A7C15ull;
  std::uint64_t h[4] = {k, k ^ 1, k ^ 2, k ^ 3};
  std::size_t i = 0;
  for (; i + 32 <= n; i += 32)
    for (int l = 0; l < 4; ++l) {
      std::uint64_t w;
      std::memcpy(&w, data + i + 8 * l, 8);
      h[l] = (h[l] ^ w) * k;
      h[l] ^= h[l] >> 29;
    }
  std::uint64_t r = n;
  for (; i < n; ++i) r = (r ^ std::uint8_t(data[i])) * k;
  for (std::uint64_t x : h) r = ((r ^ x) * k) ^ (r >> 31);
  return r;
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

void flatten(const nlohmann::json& j, const std::string& key, nlohmann::json& out) {
  if (j.is_object() && !j.empty()) {
    for (const auto& [k, v] : j.items()) flatten(v, key.empty() ? k : key + "." + k, out);
  } else {
    out[key] = j;
  }
}

// A test hook (tests/commands/checkpoint_tests.sh): APICLAB_TEST_KILL_CHECKPOINT=N kills the
// process by SIGKILL in its N-th checkpoint write, once half the bytes are in the temporary file,
// where a kill during write_file_whole would leave it.
void killed_mid_write_for_test(const std::string& path, const std::string& bytes) {
  static int writes = 0;
  const char* at = std::getenv("APICLAB_TEST_KILL_CHECKPOINT");
  if (at == nullptr || std::atoi(at) != ++writes) return;
  std::ofstream part(temporary_name_of(path), std::ios::binary | std::ios::trunc);
  part.write(bytes.data(), std::streamsize(bytes.size() / 2));
  part.flush();
  std::raise(SIGKILL);
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
  header["build"] = this_build();
  const std::string head = header.dump();
  std::string out;
  out.reserve(kPrefix + head.size() + state.size() + 8);
  out.append(kMagic, sizeof(kMagic));
  put(out, kFormatVersion);
  put(out, kByteOrder);
  put(out, std::uint64_t(head.size()));
  put(out, std::uint64_t(state.size()));
  out += head;
  out += state;
  put(out, checksum(out.data() + kPrefix, head.size() + state.size()));
  killed_mid_write_for_test(checkpoint_path(dir), out);
  write_file_whole(checkpoint_path(dir), out);
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

std::string settings_difference(const nlohmann::json& theirs, const nlohmann::json& ours) {
  nlohmann::json a = theirs, b = ours;
  a.erase("overrides");
  b.erase("overrides");
  nlohmann::json fa = nlohmann::json::object(), fb = nlohmann::json::object();
  flatten(a, "", fa);
  flatten(b, "", fb);
  for (const auto& [key, value] : fa.items()) {
    if (!fb.contains(key)) return key + " is " + shown(value) + " there, not set here";
    if (fb[key] != value)
      return key + " is " + shown(value) + " there, " + shown(fb[key]) + " here";
  }
  for (const auto& [key, value] : fb.items())
    if (!fa.contains(key)) return key + " is not set there, " + shown(value) + " here";
  return "";
}

}  // namespace apiclab::cli
