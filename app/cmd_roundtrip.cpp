// `apiclab roundtrip`: Sec 6.8 round-trip error of the solver's own G2P and P2G; CSV on stdout.
#include <cstdio>
#include <sstream>

#include "cli.hpp"
#include "commands.hpp"
#include "sim/roundtrip.hpp"

namespace apiclab::cli {

void register_roundtrip(CLI::App& root, CommandTable& table) {
  struct Options {
    std::string kernel = "quadratic", scheme = "apic";
    std::vector<int> res{16, 32, 64, 128, 256};
    int seed = 1;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand(
      "roundtrip", "Sec 6.8 round-trip transfer error: CSV resolution,dx,l2_error");
  cmd->add_option("--kernel", o->kernel, "kernel: " + choice_keys(kernel_choices()));
  cmd->add_option("--scheme", o->scheme, "scheme: pic|apic|rpic");
  cmd->add_option("--res", o->res, "grid cells per axis, comma separated")->delimiter(',');
  cmd->add_option("--seed", o->seed, "Poisson disk seed");
  table.push_back({cmd, [o] {
                     KernelType k;
                     Scheme s;
                     try {
                       k = parse_choice(kernel_choices(), o->kernel, "kernel");
                       s = parse_choice(scheme_choices(), o->scheme, "scheme");
                       std::printf("resolution,dx,l2_error\n");
                       for (int n : o->res) {
                         RoundTripResult r = roundtrip_error(k, s, n, std::uint64_t(o->seed));
                         std::printf("%d,%.17g,%.17g\n", r.resolution, r.dx, r.l2_error);
                       }
                     } catch (const std::invalid_argument& e) {
                       throw UsageError(e.what());
                     }
                     return 0;
                   }});
}

}  // namespace apiclab::cli
