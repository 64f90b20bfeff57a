// `apiclab roundtrip`: Sec 6.8 round-trip error of the solver's own G2P and P2G; CSV on stdout.
#include <cstdio>
#include <sstream>

#include "app/cli_checks.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/mpm/roundtrip.hpp"
#include "sim/scene/memory_estimate.hpp"

namespace apiclab::cli {

void register_roundtrip(CLI::App& root, CommandTable& table) {
  struct Options {
    std::string kernel = "quadratic", scheme = "apic", max_memory;
    std::vector<int> res{16, 32, 64, 128, 256};
    int seed = 1;
    int xpic_order = 2;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand(
      "roundtrip", "Sec 6.8 round-trip transfer error: CSV resolution,dx,l2_error");
  cmd->add_option("--kernel", o->kernel,
                  "kernel: " + choice_keys(kernel_choices()) + " [default: quadratic]");
  std::string probed;  // every scheme the probe runs (roundtrip_refusal)
  for (const auto& c : scheme_choices())
    if (roundtrip_refusal(c.value).empty())
      probed += (probed.empty() ? "" : "|") + std::string(c.key);
  cmd->add_option("--scheme", o->scheme, "scheme: " + probed + " [default: apic]");
  cmd->add_option("--xpic-order", o->xpic_order,
                  "XPIC's m with --scheme xpic (solver.xpic_order) [allowed: 1-1000; default: 2]")
      ->check(whole_number(1, 1000));
  cmd->add_option("--res", o->res,
                  "grid cells per axis, comma separated [allowed: 4 or more; default: "
                  "16,32,64,128,256]")
      ->delimiter(',')
      ->check(whole_number(4, 1 << 30));
  cmd->add_option("--seed", o->seed, "Poisson disk seed [allowed: 0 or more; default: 1]")
      ->check(whole_number(0, 2147483647));
  cmd->add_option("--max-memory", o->max_memory,
                  "refuse a resolution whose estimated memory exceeds this: BYTES (e.g. 8G), auto "
                  "or none [default: auto = the available memory]");
  table.push_back({cmd, [o] {
                     KernelType k;
                     Scheme s;
                     try {
                       k = parse_choice(kernel_choices(), o->kernel, "kernel");
                       s = parse_choice(scheme_choices(), o->scheme, "scheme");
                     } catch (const std::invalid_argument& e) {
                       throw UsageError(e.what());
                     }
                     if (const std::string why = roundtrip_refusal(s); !why.empty())
                       throw UsageError(why);
                     const int m = o->xpic_order;
                     // Every resolution is checked before the first runs.
                     const auto gb = max_memory_gb(o->max_memory);
                     const auto cap =
                         gb ? std::optional<double>(*gb * 1e9) : available_memory_bytes();
                     for (int n : o->res) {
                       const MemoryEstimate need = estimate_roundtrip_memory(n, s, m);
                       check_memory(need, cap, "roundtrip --res " + std::to_string(n));
                     }
                     std::printf("resolution,dx,l2_error\n");
                     try {
                       for (int n : o->res) {
                         RoundTripResult r = roundtrip_error(k, s, n, std::uint64_t(o->seed), m);
                         std::printf("%d,%.17g,%.17g\n", r.resolution, r.dx, r.l2_error);
                       }
                     } catch (const std::invalid_argument& e) {
                       throw UsageError(e.what());
                     }
                     return 0;
                   }});
}

}  // namespace apiclab::cli
