// capflow/app/sweep_directory: the directory of a sweep (app/sweep.h) - its rules (what it may
// hold, --overwrite), its case control files, the states of its cases read from their run
// directories, its summary sweep.csv and its Slurm script.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "control/run_events.h"
#include "control/sweep.h"

namespace capflow::app {

enum class CaseStatus { New, Done, Failed, Interrupted };
const char* to_string(CaseStatus s);

struct CaseState {
  CaseStatus status = CaseStatus::New;
  control::RunEnd end;
  bool has_checkpoint = false;
};
// A case's state from its run directory (its "end" event, control/run_events.h).
CaseState state_of(const std::filesystem::path& run);

// The sweep directory before anything is written into it (app/sweep.h's rules): UserError when
// it cannot hold this sweep.
void prepare_sweep_directory(const control::SweepPlan& plan, bool overwrite);

// The case control files: written when absent, refused (UserError) when they differ from the
// sweep's.
void write_case_files(const control::SweepPlan& plan);

// The cases' states: done and failed are final and kept; the others are read again from their
// run directories (events.jsonl) at each summary, since other ranks may have moved them on.
struct KnownStates {
  std::vector<CaseState> states;
  const CaseState& refresh(size_t i, const std::filesystem::path& run) {
    if (states.size() <= i) states.resize(i + 1);
    CaseState& s = states[i];
    if (s.status != CaseStatus::Done && s.status != CaseStatus::Failed) s = state_of(run);
    return s;
  }
};

// sweep.csv: one row per case, its values, status, exit code, end reason and final t, D, L, S,
// W, steps (under sweep.csv.lock: of several launcher ranks the last one to write read last).
void write_summary(const control::SweepPlan& plan, KnownStates* known);

// sweep.sbatch: a Slurm job array running `exe sweep sweep_file --case N`, one task per case.
void write_slurm(const control::SweepPlan& plan, const std::string& sweep_file,
                 const std::string& exe);

}  // namespace capflow::app
