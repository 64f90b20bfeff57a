// apiclab: research viewer for hybrid particle/grid simulation. Subcommand dispatch.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>

#include "app/cli_checks.hpp"
#include "app/output_file.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/scene/input_file.hpp"
#include "sim/scene/message_text.hpp"
#include "sim/scene/scene.hpp"

namespace {

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// The deepest subcommand the command line reached: its options are the ones in question.
const CLI::App* reached(const CLI::App& root) {
  const CLI::App* app = &root;
  while (!app->get_subcommands().empty()) app = app->get_subcommands().front();
  return app;
}

// The first argument CLI11 could not place, with the nearest option or command as a suggestion.
std::string unexpected_text(CLI::App& root) {
  const CLI::App* app = reached(root);
  const std::vector<std::string> args = root.remaining(true);
  if (args.empty()) return "unexpected arguments";
  const std::string& arg = args.front();
  const std::string name = arg.substr(0, arg.find('='));
  std::vector<std::string> candidates;
  if (name.rfind("-", 0) == 0) {
    for (const CLI::Option* o : app->get_options())
      for (const std::string& n : o->get_lnames()) candidates.push_back("--" + n);
  } else if (app == &root) {
    for (const CLI::App* sub : root.get_subcommands([](CLI::App*) { return true; }))
      candidates.push_back(sub->get_name());
  }
  const std::string near = apiclab::cli::nearest(name, candidates);
  return "unexpected argument '" + apiclab::message_text(arg, 60) + "'" +
         (near.empty() ? "" : " (did you mean '" + near + "'?)");
}

// The part of CLI11's message before its first ": " or " =", naming the option.
std::string option_named(const std::string& what, const char* after) {
  const auto at = what.find(after);
  return at == std::string::npos ? std::string() : what.substr(0, at);
}

// CLI11's parse errors in the project's words: the one place its exceptions are caught. The
// options' own checks (app/cli_checks.hpp) word the values they refuse; the rest is worded here.
std::string parse_error_text(const CLI::ParseError& e, CLI::App& root) {
  const std::string what = one_line(e.what());
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) return unexpected_text(root);
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e)) {
    const std::string name = option_named(what, ":");
    return (name.empty() ? std::string("an option") : name) + " needs a value";
  }
  if (dynamic_cast<const CLI::ConversionError*>(&e)) {
    // "Could not convert: --frames = 2.5" (an option without its kind check): name and value.
    const std::string prefix = "Could not convert: ";
    if (what.rfind(prefix, 0) == 0) {
      const std::string rest = what.substr(prefix.size());
      const std::string name = option_named(rest, " = ");
      if (!name.empty())
        return name + ": cannot read the value '" +
               apiclab::message_text(rest.substr(name.size() + 3), 60) + "'";
    }
    const std::string name = option_named(what, ":");
    return (name.empty() ? std::string("an option") : name) + " takes no value here";
  }
  if (dynamic_cast<const CLI::RequiredError*>(&e) && what == "A subcommand")
    return "a command is required";
  return apiclab::message_text(what);
}

// The root's description: both solver families, with the schemes of the first.
std::string root_description() {
  std::string schemes = apiclab::choice_keys(apiclab::scheme_choices());
  for (char& c : schemes)
    if (c == '|') c = ' ';
  return "apiclab: hybrid particle/grid simulation, two solver families (scene key "
         "solver.method):\n"
         "  mpm  the Material Point Method with nine particle-grid transfer schemes:\n"
         "       " +
         schemes +
         " (Jiang et al. 2017 and later)\n"
         "  eol  the Eulerian-on-Lagrangian solver of Fan et al. 2013 (eulerian: its Eulerian "
         "baseline)";
}

std::string root_footer() {
  return "Exit codes:\n"
         "  0         success (also --help, --version)\n"
         "  2         bad input, or an output that cannot be written (one line on stderr)\n"
         "  3         the simulation blew up\n"
         "  130, 143  stopped by SIGINT, SIGTERM\n"
         "The manual: docs/cli.md.";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace apiclab::cli;
  CLI::App root{root_description()};
  root.require_subcommand(0, 1);
  root.set_version_flag("--version", version_text());
  CommandTable table;
  register_run(root, table);
  register_roundtrip(root, table);
  register_bench(root, table);
  register_list(root, table);
  register_docs(root, table);
  register_sweep(root, table);
#ifdef APICLAB_HAVE_RENDER
  register_render(root, table);
#endif
#ifdef APICLAB_HAVE_GUI
  register_gui(root, table);
#endif
#ifdef APICLAB_HAVE_FIGURES
  register_figures(root, table);
#endif
  root.footer(root_footer());  // after the subcommands: they would inherit it
  check_option_kinds(root);
  try {
    root.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return root.exit(e);
  } catch (const CLI::ParseError& e) {
    // Documented exit code 2 and one line, whatever CLI11's own code (104-109).
    std::string help = "apiclab --help";
    for (const CLI::App* sub : root.get_subcommands())
      help = "apiclab " + sub->get_name() + " --help";
    std::fprintf(stderr, "apiclab: %s (see %s)\n", parse_error_text(e, root).c_str(), help.c_str());
    return 2;
  }
  try {
    for (auto& c : table)
      if (c.app->parsed()) return c.action();
#ifdef APICLAB_HAVE_GUI
    if (gui_available()) return run_default_gui();
#endif
    std::cout << root.help();
    return 0;
  } catch (const apiclab::SceneError& e) {
    std::fprintf(stderr, "apiclab: %s\n", e.what());
  } catch (const UsageError& e) {
    std::fprintf(stderr, "apiclab: %s\n", e.what());
  } catch (const apiclab::WriteError& e) {
    // A full disk or a file size limit: "cannot write FILE: REASON" (docs/outputs.md).
    std::fprintf(stderr, "apiclab: %s\n", e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the code did not check first: the path and the cause, in the project's words.
    const std::string path = e.path1().string();
    std::fprintf(stderr, "apiclab: cannot use '%s': %s\n", apiclab::message_text(path).c_str(),
                 apiclab::path_error_text(e.code(), path).c_str());
  } catch (const std::bad_alloc&) {
    // The memory cap passed, yet an allocation failed: not the library's "std::bad_alloc".
    std::fprintf(stderr,
                 "apiclab: out of memory: an allocation failed (a lower --max-memory refuses such "
                 "a scene before it starts; docs/cli.md, Memory cap)\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "apiclab: error: %s\n", e.what());
  }
  return 2;
}
