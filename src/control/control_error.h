// capflow/control/control_error: the user-error type of the control module.
//
// Every problem of a control document is a ControlIssue: the JSON path it is at ("" for the
// document as a whole, e.g. "ca[2].ramp.rate"), and a message naming the bad value and what is
// valid. ControlError carries all issues of one document (they are collected, not stopped at
// the first) and names the document (a file path, "--t-end", "<checkpoint> (stored control)").
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

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

}  // namespace capflow::control
