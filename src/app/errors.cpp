// capflow/app/errors: see errors.h.
#include "app/errors.h"

#include <new>

#include "app/console.h"
#include "control/control_error.h"
#include "files/atomic_write.h"
#include "files/input_file.h"

namespace capflow::app {

int exit_code_of(const std::exception& e) {
  if (dynamic_cast<const UserError*>(&e) || dynamic_cast<const control::ControlError*>(&e) ||
      dynamic_cast<const files::InputError*>(&e))
    return exit_code::kUserError;
  if (dynamic_cast<const OutputError*>(&e) || dynamic_cast<const files::WriteError*>(&e))
    return exit_code::kOutputFailed;
  return exit_code::kInternal;
}

int report_failure(const std::exception& e) {
  const int code = exit_code_of(e);
  switch (code) {
    case exit_code::kUserError:
      console::err(std::string("capflow: error: ") + e.what());
      break;
    case exit_code::kOutputFailed:
      console::err(std::string("capflow: output error: ") + e.what());
      break;
    default:
      if (dynamic_cast<const std::bad_alloc*>(&e))
        console::err(
            "capflow: internal error: out of memory (std::bad_alloc): an allocation capflow "
            "should have bounded; please report the command that caused it");
      else
        console::err(std::string("capflow: internal error: ") + e.what());
  }
  return code;
}

}  // namespace capflow::app
