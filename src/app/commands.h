// capflow/app/commands: subcommand registry of the capflow executable.
//
// Each cmd_*.cpp file defines one subcommand with
//   static int my_cmd(...);  CAPFLOW_COMMAND(order, setup_function)
// where setup_function(CLI::App& root) adds the subcommand, its options and a callback.
// Callbacks report user errors by throwing capflow::app::UserError (printed as
// "capflow: error: ..." with exit code 2), output failures by OutputError (exit 5); anything
// else is an internal error (exit 3). app/errors.h lists the codes.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "app/errors.h"

namespace capflow::app {

using CommandSetup = std::function<void(CLI::App& root)>;
bool register_command(int order, CommandSetup setup);

// Exit code a subcommand callback sets (default 0).
void set_exit_code(int code);

}  // namespace capflow::app

#define CAPFLOW_COMMAND_CAT2(a, b) a##b
#define CAPFLOW_COMMAND_CAT(a, b) CAPFLOW_COMMAND_CAT2(a, b)
#define CAPFLOW_COMMAND(order, setup)                                                    \
  static const bool CAPFLOW_COMMAND_CAT(capflow_command_registered_, __LINE__) =          \
      ::capflow::app::register_command(order, setup)
