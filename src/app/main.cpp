// capflow: spectral boundary element simulation of elastic capsules in Stokes flow.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <string>
#include <utility>
#include <vector>

#include "app/commands.h"
#include "app/console.h"
#include "app/heap_policy.h"
#include "app/worker_team.h"
#include "parallel/team.h"

namespace capflow::app {
namespace {
std::vector<std::pair<int, CommandSetup>>& registry() {
  static std::vector<std::pair<int, CommandSetup>> r;
  return r;
}
int g_exit_code = 0;
}  // namespace

bool register_command(int order, CommandSetup setup) {
  registry().emplace_back(order, std::move(setup));
  return true;
}
void set_exit_code(int code) {
  g_exit_code = code;
}
}  // namespace capflow::app

int main(int argc, char** argv) {
  using namespace capflow::app;
  // A console that goes away (`| head`, a closed ssh pipe) must not end capflow: writes to it fail
  // with EPIPE instead (app/console.h), and runs go on.
  std::signal(SIGPIPE, SIG_IGN);
  // Started with stdin, stdout or stderr closed, the first files capflow opens would take their
  // numbers, and console lines would land in them (a run's CSV): they point to /dev/null then.
  for (int fd = 0; fd <= 2; ++fd)
    if (::fcntl(fd, F_GETFD) < 0) {
      const int null = ::open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
      if (null >= 0 && null != fd) {
        ::dup2(null, fd);
        ::close(null);
      }
    }
  // A file-size limit makes a write fail (an output failure, exit 5, naming the file) instead of
  // killing the process, for every command.
  std::signal(SIGXFSZ, SIG_IGN);
  keep_freed_heap();
  // Under an MPI launcher the ranks > 0 serve rank 0's velocity evaluations (app/worker_team.h);
  // rank 0 runs the command and ends their service on every way out of main.
  // Only run and steady use the ranks this way; a sweep under a launcher deals out its cases
  // (app/sweep.h; with --ranks-per-case it starts MPI itself and its groups serve this way) and
  // every other command runs on each rank as one process.
  const bool team_command =
      argc > 1 && (std::string(argv[1]) == "run" || std::string(argv[1]) == "steady");
  if (team_command) capflow::parallel::start(&argc, &argv);
  if (capflow::parallel::rank() > 0) {
    const int code = serve_team();
    capflow::parallel::finish();
    return code;
  }
  struct EndTeam {
    ~EndTeam() {
      end_workers();
      capflow::parallel::finish();
    }
  } end_team;
  CLI::App app{"capflow - elastic capsules in Stokes flow by the spectral boundary element method"};
  app.require_subcommand(1);
  auto& reg = registry();
  std::stable_sort(reg.begin(), reg.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, setup] : reg) setup(app);
  app.set_version_flag("--version", std::string("capflow ") + CAPFLOW_VERSION + "\nbuilt with " +
                                        CAPFLOW_ARCH_FLAGS);
  // A first argument that is neither an option nor a command: name it and the commands (CLI11
  // would only say that a subcommand is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == argv[1];
    }
    if (!known) {
      console::err("capflow: error: unknown command '" + std::string(argv[1]) +
                   "' (commands: " + names + "; capflow --help)");
      return exit_code::kUserError;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help / --version exit 0; every command-line error is "invalid input" (2), as documented.
    const int code = app.exit(e);
    return code == 0 ? 0 : exit_code::kUserError;
  } catch (const std::exception& e) {
    return report_failure(e);
  }
  return g_exit_code;
}
