// `ovpc`: the OVPC testbed's command line.
#include <iostream>
#include <string>

#include "commands.h"

int main(int argc, char** argv) {
  using namespace ovpc::apps;
  CLI::App app{"ovpc - OVPC Mesh free-space mapping and closed-loop testbed for ground robots"};
  app.require_subcommand(1, 1);
  app.set_version_flag("--version", std::string("ovpc 0.1.0"));
  const Runner mesh = RegisterMesh(app);
  const Runner synth = RegisterSynth(app);
  const Runner run = RegisterRun(app);
  const Runner suite = RegisterSuite(app);
  const Runner family = RegisterFamily(app);
  const Runner merge = RegisterMerge(app);
  const Runner compare = RegisterCompare(app);
  bool known = argc < 2 || argv[1][0] == '-';
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    known = known || sub->check_name(argv[1]);
  }
  if (!known) {
    std::cerr << "ovpc: error: unknown command '" << argv[1] << "' (expected one of: mesh, synth, run, suite, family, merge, compare; see ovpc --help)\n";
    return kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ovpc: error: " << e.what() << " (see ovpc --help)\n";
    return kExitBadInput;
  }
  try {
    if (app.got_subcommand("mesh")) return mesh();
    if (app.got_subcommand("synth")) return synth();
    if (app.got_subcommand("run")) return run();
    if (app.got_subcommand("suite")) return suite();
    if (app.got_subcommand("family")) return family();
    if (app.got_subcommand("merge")) return merge();
    if (app.got_subcommand("compare")) return compare();
  } catch (const BadInput& e) {
    std::cerr << "ovpc: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    std::cerr << "ovpc: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "ovpc: failed: " << e.what() << "\n";
    return kExitFailure;
  }
  return kExitBadInput;
}
