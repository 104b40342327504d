// capflow reference [--dictionary]: prints the control-file reference (docs/control.md) or the
// fuzzing dictionary (tests/fuzz/control.dict), both generated from the schema
// (control/schema.h). Tests fail when the committed files differ from this output:
//   capflow reference > docs/control.md
//   capflow reference --dictionary > tests/fuzz/control.dict
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "control/schema.h"

namespace capflow::app {
namespace {

void setup_reference(CLI::App& root) {
  auto dictionary = std::make_shared<bool>(false);
  CLI::App* c = root.add_subcommand(
      "reference", "Print the control-file reference (docs/control.md) generated from the schema");
  c->add_flag("--dictionary", *dictionary,
              "Print the libFuzzer dictionary of the control file instead");
  c->callback([dictionary] {
    std::cout << (*dictionary ? control::control_fuzz_dictionary()
                              : control::control_reference_markdown());
  });
}

}  // namespace

CAPFLOW_COMMAND(40, setup_reference);

}  // namespace capflow::app
