// capflow/control/control_file: JSON control file -> validated ControlOptions.
//
// The only place in capflow that parses JSON. Every problem is reported with its JSON path
// (e.g. "ca[2].ramp.rate"), the offending value and the valid range or alternatives; unknown
// keys get a "did you mean" suggestion. All problems of a file are collected and reported
// together (ControlError::issues). Warnings flag legal but suspicious values (e.g. a time step
// above the stability estimate dt < Ca_min dx_min, paper eq. 16).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "capsule/capsule.h"
#include "control/options.h"

namespace capflow::control {

struct ControlIssue {
  std::string path;     // JSON path, "" for the whole document
  std::string message;  // what is wrong, the value, and what is valid
  std::string str() const { return path.empty() ? message : path + ": " + message; }
};

class ControlError : public std::runtime_error {
 public:
  ControlError(const std::string& source, std::vector<ControlIssue> issues);
  const std::vector<ControlIssue>& issues() const { return issues_; }

 private:
  std::vector<ControlIssue> issues_;
};

struct ParsedControl {
  ControlOptions options;
  std::vector<ControlIssue> warnings;
};

// Parses and validates a control document. `source` names it in error messages.
// Throws ControlError listing every problem.
ParsedControl parse_control(const std::string& text, const std::string& source = "control file");
// Reads the file first (ControlError if it cannot be read).
ParsedControl load_control_file(const std::string& path);

// The effective control file (every key with its value, defaults filled in), as JSON text.
std::string to_json_text(const ControlOptions& options);

// The solver options a control file asks for (capsule::Capsule's constructor argument).
capsule::DynamicsOptions dynamics_options(const ControlOptions& options);

// The spectral-element mesh the "mesh" options describe.
std::unique_ptr<geometry::Mesh> make_mesh(const MeshOptions& mesh);

// Smallest node spacing of the reference mesh (for the time-step warning).
double min_node_spacing(const MeshOptions& mesh);

std::string to_string(RunState s);

}  // namespace capflow::control
