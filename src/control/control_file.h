// capflow/control/control_file: JSON control file -> validated ControlOptions.
//
// The only place in capflow that parses JSON. Every problem is reported with its JSON path
// (e.g. "ca[2].ramp.rate"), the offending value and the valid range or alternatives; unknown
// keys get a "did you mean" suggestion. All problems of a file are collected and reported
// together (ControlError::issues). Warnings flag legal but suspicious values (e.g. a fixed time
// step near or above the measured stability limit, control/stability.h).
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "capsule/capsule.h"
#include "control/control_error.h"
#include "control/options.h"

namespace capflow::control {

struct ParsedControl {
  ControlOptions options;
  std::vector<ControlIssue> warnings;
};

// Parses and validates a control document (the schema of control/schema.h, the limits of
// control/limits.h). `source` names it in error messages. Throws ControlError listing every
// problem.
ParsedControl parse_control(const std::string& text, const std::string& source = "control file");
// The bytes of a control file under files/input_file.h's rule (a regular file of at most
// kMaxControlBytes, never blocking): ControlError naming the file when it cannot be read.
std::string read_control_text(const std::string& path);
// Reads the file first through control/json_input.h's gate (a regular file, at most
// kMaxControlBytes, never blocking): ControlError if it cannot be read.
ParsedControl load_control_file(const std::string& path);

// The run.* keys (run.state, run.checkpoint_now) of a control document that is refused as a
// whole, when it is a JSON object whose "run" object is itself valid: a stop or a pause saved in
// a file that does not validate otherwise (a t_end too far for a new dt, say) is still honoured.
// nullopt when there are none to read.
std::optional<RunOptions> run_keys_of(const std::string& text);

// Problems of t_end for a run at time t_now (0 for a new run): t_end at least half a step past
// t_now (fresh runs: at least dt), and at most kMaxSteps steps to go. Paths are "time.t_end".
std::vector<ControlIssue> time_issues(const TimeOptions& time, double t_now);

// The effective control file (every key with its value, defaults filled in), as JSON text.
std::string to_json_text(const ControlOptions& options);

// The solver options a control file asks for (capsule::Capsule's constructor argument).
capsule::DynamicsOptions dynamics_options(const ControlOptions& options);

// The spectral-element mesh the "mesh" options describe.
std::unique_ptr<geometry::Mesh> make_mesh(const MeshOptions& mesh);

// Smallest node spacing of the reference mesh (for the time-step warning, control/stability.h).
double min_node_spacing(const MeshOptions& mesh);

std::string to_string(RunState s);

}  // namespace capflow::control
