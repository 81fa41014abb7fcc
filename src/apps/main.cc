// partslam: the command-line front end. Each subcommand lives in its own cmd_*.cc file and is
// registered here; errors from bad input are printed as "partslam: error: ..." with exit code 1.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "apps/commands.h"
#include "apps/mpi_split.h"

int main(int argc, char** argv) {
  const partslam::apps::MpiSession mpi(&argc, &argv);  // MPI only under mpirun (apps/mpi_split.h)
  CLI::App app{"PartSLAM: fast, succinct 1-to-N matching of 2D laser maps"};
  app.set_version_flag("--version", std::string("partslam ") + PARTSLAM_VERSION);
  app.require_subcommand(1);
  partslam::apps::register_all(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::Success&) {  // --print-config: done
    return 0;
  } catch (const partslam::apps::ExitStatus& e) {  // results written, and said not to be trusted
    return e.status;
  } catch (const CLI::ParseError& e) {
    // Bad command lines fail like bad input: one prefixed line, exit code 1 (not CLI11's own codes).
    std::cerr << "partslam: error: " << e.what() << " (see 'partslam --help')\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "partslam: error: " << e.what() << "\n";
    partslam::apps::MpiSession::abort_all(1);
    return 1;
  }
  return 0;
}
