// capflow/app/console: what capflow prints on its console (stderr, and stdout for results that
// are meant to be piped), one place for all of it.
//
//   * Every line is made printable first (files/printable.h): bytes taken from input files or
//     the command line cannot drive the terminal (ESC sequences, BEL, C1 controls).
//   * Each line is one write(2). A write that fails (EPIPE: the reader of a pipe is gone, `| head`;
//     EIO: the terminal was hung up) marks that stream as gone: later lines to it are dropped,
//     nothing throws and no signal ends the process (main ignores SIGPIPE). A run's console is a
//     convenience; its run directory (run.log) is the record, and the run goes on.
// Thread-safe (the renderer thread logs through it too).
#pragma once

#include <string>

namespace capflow::app::console {

// A line on stderr (a newline is added).
void err(const std::string& line);
// A line on stdout (a newline is added).
void out(const std::string& line);
// The progress line on a terminal: rewritten in place ("\r\033[K" + line, no newline).
void status(const std::string& line);

// True once a write to stderr failed; reason() says why ("Broken pipe").
bool err_gone();
std::string err_gone_reason();

// Forget that a stream was gone (its descriptor was pointed somewhere else: a sweep's case log).
void reset();

}  // namespace capflow::app::console
