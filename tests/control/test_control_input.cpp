// Hostile and careless control input (Milestone 7): every case is refused with the key named, or
// accepted as documented - never a crash, a hang, a silent overwrite or an unbounded run.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "control/control_file.h"
#include "control/edit.h"
#include "control/limits.h"
#include "control/schema.h"

using namespace capflow::control;
namespace fs = std::filesystem;

namespace {

// The issues of a refused document ("" = accepted).
std::string issues_of(const std::string& text) {
  try {
    parse_control(text, "t.json");
  } catch (const ControlError& e) {
    std::string all;
    for (const auto& i : e.issues()) all += i.str() + "\n";
    return all;
  }
  return "";
}

std::string file_issues(const std::string& path) {
  try {
    load_control_file(path);
  } catch (const ControlError& e) {
    return e.what();
  }
  return "";
}

void expect_contains(const std::string& s, const std::string& part) {
  EXPECT_NE(s.find(part), std::string::npos) << "'" << part << "' not in: " << s;
}

fs::path scratch(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("capflow_ctl_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST(ControlInput, DeepNestingIsRefusedWithoutRecursion) {
  for (const size_t depth : {size_t(kMaxControlDepth + 1), size_t(70000), size_t(100000)}) {
    const std::string doc =
        "{\"ca\": 0.4, \"x\": " + std::string(depth, '[') + std::string(depth, ']') + "}";
    const std::string m = issues_of(doc);
    expect_contains(m, "nested deeper than " + std::to_string(kMaxControlDepth));
    expect_contains(m, "x[0]");
  }
  const std::string objects = [] {
    std::string s = "{\"ca\": 0.4, \"mesh\": ";
    for (int i = 0; i < 100000; ++i) s += "{\"a\": ";
    return s;  // (unterminated as well: refused at the depth limit first)
  }();
  expect_contains(issues_of(objects), "nested deeper");
}

TEST(ControlInput, NumbersOutsideDoubleRangeNameTheKey) {
  std::string m = issues_of(R"({"ca": 0.4, "time": {"t_end": 1e400}})");
  expect_contains(m, "time.t_end: number 1e400 is outside the range of a double");
  m = issues_of(R"({"ca": [{"ca": 0.3}, {"ramp": {"to": 1, "rate": -1e999}}]})");
  expect_contains(m, "ca[1].ramp.rate");
  expect_contains(issues_of(R"({"ca": 1e400})"), "ca: number 1e400");
  // huge integers become doubles and are range-checked like any value
  expect_contains(issues_of(R"({"ca": 0.4, "mesh": {"nb": 123456789012345678901234567890}})"),
                  "mesh.nb: expected an integer");
  expect_contains(issues_of(R"({"ca": 0.4, "mesh": {"nb": 18446744073709551615}})"),
                  "mesh.nb: value 18446744073709551615 is out of range");
}

TEST(ControlInput, DuplicateKeysAreRefused) {
  std::string m = issues_of(R"({"ca": 0.4, "time": {"dt": 0.001}, "time": {"t_end": 3}})");
  expect_contains(m, "time: key \"time\" is given twice");
  m = issues_of(R"({"ca": 0.4, "time": {"dt": 0.001, "dt": 0.002}})");
  expect_contains(m, "time.dt: key \"dt\" is given twice");
  m = issues_of(R"({"ca": [{"ca": 0.3, "hold": 1, "hold": 2}]})");
  expect_contains(m, "ca[0].hold: key \"hold\" is given twice");
}

TEST(ControlInput, TimeStepFloorAndRunLength) {
  expect_contains(issues_of(R"({"ca": 0.4, "time": {"dt": 1e-7}})"),
                  "time.dt: value 1e-07 is out of range");
  expect_contains(issues_of(R"({"ca": 0.4, "time": {"dt": 0.01, "t_end": 0.005}})"),
                  "time.t_end: value 0.005 is below the time step dt = 0.01");
  expect_contains(issues_of(R"({"ca": 0.4, "time": {"dt": 1e-6, "t_end": 1000}})"),
                  "at most 1e+07 steps");
  EXPECT_EQ(issues_of(R"({"ca": 0.4, "time": {"dt": 0.01, "t_end": 0.01}})"), "");
  // resuming: t_end must lie after the run's time
  TimeOptions t;
  t.dt = 0.01;
  t.t_end = 2.0;
  EXPECT_TRUE(time_issues(t, 1.0).empty());
  ASSERT_EQ(time_issues(t, 2.0).size(), 1u);
  expect_contains(time_issues(t, 2.0)[0].message, "not after the run's time t = 2");
}

TEST(ControlInput, DescriptionMayBeEmptyAndIsCapped) {
  EXPECT_EQ(issues_of(R"({"ca": 0.4, "description": ""})"), "");
  const std::string big =
      "{\"ca\": 0.4, \"description\": \"" + std::string(kMaxDescriptionBytes + 1, 'a') + "\"}";
  expect_contains(issues_of(big), "description: is 65537 bytes long");
}

TEST(ControlInput, OnlyRegularFilesOfBoundedSizeAreRead) {
  const fs::path d = scratch("files");
  // a FIFO nobody writes to: refused at once, not a blocked reader
  ASSERT_EQ(::mkfifo((d / "fifo.json").c_str(), 0644), 0);
  auto t0 = std::chrono::steady_clock::now();
  expect_contains(file_issues((d / "fifo.json").string()), "is a FIFO");
  EXPECT_LT(seconds_since(t0), 5.0);
  // a symlink to /dev/zero: refused, not read until memory runs out
  fs::create_symlink("/dev/zero", d / "zero.json");
  t0 = std::chrono::steady_clock::now();
  expect_contains(file_issues((d / "zero.json").string()), "is a device");
  EXPECT_LT(seconds_since(t0), 5.0);
  expect_contains(file_issues(d.string()), "is a directory");
  // larger than the cap
  {
    std::ofstream f(d / "big.json");
    f << "{\"ca\": 0.4, \"description\": \"" << std::string(kMaxControlBytes, 'a') << "\"}";
  }
  expect_contains(file_issues((d / "big.json").string()), "larger than 1 MiB");
  // a symlink to a regular file is followed
  {
    std::ofstream f(d / "real.json");
    f << R"({"ca": 0.4})";
  }
  fs::create_symlink(d / "real.json", d / "link.json");
  EXPECT_EQ(file_issues((d / "link.json").string()), "");
  fs::remove_all(d);
}

TEST(ControlInput, ErrorMessagesOfHugeValuesStayShort) {
  std::string list = "1";
  for (int i = 0; i < 1000; ++i) list += ", 1";
  const std::string doc = "{\"ca\": 0.4, \"mesh\": {\"nb\": [" + list + "]}}";
  const std::string m = issues_of(doc);
  expect_contains(m, "mesh.nb: expected an integer");
  EXPECT_LT(m.size(), 400u);
}

// ---- the schema as data -------------------------------------------------------------------------

namespace {
std::string committed(const std::string& rel) {
  std::ifstream f(std::string(CAPFLOW_SOURCE_DIR) + "/" + rel);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(ControlSchema, GeneratedReferenceIsCurrent) {
  EXPECT_EQ(committed("docs/control.md"), control_reference_markdown())
      << "docs/control.md is stale: run build/src/app/capflow reference > docs/control.md";
}

TEST(ControlSchema, FuzzDictionaryIsCurrent) {
  EXPECT_EQ(committed("tests/fuzz/control.dict"), control_fuzz_dictionary())
      << "tests/fuzz/control.dict is stale: run build/src/app/capflow reference --dictionary > "
         "tests/fuzz/control.dict";
}

TEST(ControlSchema, EveryFieldIsDocumentedAndCheckedAtItsPath) {
  const std::string reference = control_reference_markdown();
  for (const FieldInfo& f : control_fields()) {
    EXPECT_FALSE(f.doc.empty()) << f.path;
    EXPECT_FALSE(f.valid.empty()) << f.path;
    EXPECT_FALSE(f.default_value.empty()) << f.path;
    EXPECT_NE(reference.find("| `" + f.path + "` |"), std::string::npos) << f.path;
    // a value of the wrong kind (an object) at the field's path is refused at that path
    std::string doc = f.path == "ca" ? "{" : "{\"ca\": 0.4, ";
    std::string close = "}";
    for (size_t s = 0, e;; s = e + 1) {
      e = f.path.find('.', s);
      const std::string key = f.path.substr(s, e == std::string::npos ? std::string::npos : e - s);
      doc += "\"" + key + "\": ";
      if (e == std::string::npos) break;
      doc += "{";
      close += "}";
    }
    doc += "{\"zz\": 1}" + close;
    const std::string m = issues_of(doc);
    EXPECT_NE(m.find(f.path + ": "), std::string::npos) << doc << "\n" << m;
  }
}

TEST(ControlSchema, LiveAndFrozenFollowTheTable) {
  const ControlOptions a = parse_control(R"({"ca": 0.45})").options;
  for (const FieldInfo& f : control_fields()) {
    if (f.path != "time.dt" && f.path != "capsule.C") continue;
    const ControlOptions b =
        parse_control(f.path == "time.dt" ? R"({"ca": 0.45, "time": {"dt": 0.002}})"
                                          : R"({"ca": 0.45, "capsule": {"C": 2}})")
            .options;
    const EditResult r = apply_edit(a, b);
    if (f.mutability == Mutability::Live) {
      ASSERT_EQ(r.applied.size(), 1u) << f.path;
      EXPECT_EQ(r.applied[0].path, f.path);
    } else {
      ASSERT_EQ(r.refused.size(), 1u) << f.path;
      EXPECT_EQ(r.refused[0].path, f.path);
    }
  }
}

TEST(ControlEdit, CommandLineOverridesAreNotEdits) {
  // The file says output.dir "a" and t_end 20; the run was started with -o b --t-end 5. Saving
  // the file with only "ca" changed applies ca and refuses nothing (no spurious output.dir).
  const ControlOptions file = parse_control(R"({"ca": 0.3, "output": {"dir": "a"}})").options;
  ControlOptions effective = file;
  effective.output.dir = "b";
  effective.time.t_end = 5;
  const ControlOptions saved = parse_control(R"({"ca": 0.5, "output": {"dir": "a"}})").options;
  const EditResult r = apply_edit(effective, file, saved);
  EXPECT_TRUE(r.refused.empty()) << r.refused[0].path;
  ASSERT_EQ(r.applied.size(), 1u);
  EXPECT_EQ(r.applied[0].path, "ca");
  EXPECT_EQ(r.merged.output.dir, "b");
  EXPECT_EQ(r.merged.time.t_end, 5);
  // An edit of t_end in the file does apply (and replaces the command line's value).
  const ControlOptions t =
      parse_control(R"({"ca": 0.5, "output": {"dir": "a"}, "time": {"t_end": 8}})").options;
  const EditResult r2 = apply_edit(r.merged, saved, t);
  ASSERT_EQ(r2.applied.size(), 1u);
  EXPECT_EQ(r2.applied[0].path, "time.t_end");
  EXPECT_EQ(r2.applied[0].old_value, "5.0");
  EXPECT_EQ(r2.merged.time.t_end, 8);
  // A frozen key changed and changed back: refused once, then nothing to refuse.
  const ControlOptions nb =
      parse_control(
          R"({"ca": 0.5, "output": {"dir": "a"}, "time": {"t_end": 8}, "mesh": {"nb": 9}})")
          .options;
  EXPECT_EQ(apply_edit(r2.merged, t, nb).refused.size(), 1u);
  EXPECT_TRUE(apply_edit(r2.merged, nb, t).refused.empty());
}

TEST(ControlInput, ContinuationIsReadCheckedAndWrittenBack) {
  const ControlOptions o =
      parse_control(R"({"ca": {"continuation": {"from": 0.15, "to": 3, "step": 0.05}}})").options;
  ASSERT_TRUE(o.ca.continuation.has_value());
  EXPECT_EQ(o.ca.continuation->from, 0.15);
  EXPECT_EQ(o.ca.continuation->to, 3.0);
  EXPECT_EQ(o.ca.continuation->step, 0.05);
  EXPECT_EQ(o.ca.continuation->after_fold, 3);  // the default
  EXPECT_TRUE(o.ca.segments.empty());
  // Written back (control.json of a run directory) and read again: the same.
  const ControlOptions again = parse_control(to_json_text(o)).options;
  ASSERT_TRUE(again.ca.continuation.has_value());
  EXPECT_EQ(again.ca.continuation->to, 3.0);
  EXPECT_EQ(again.ca.continuation->after_fold, 3);

  expect_contains(issues_of(R"({"ca": {"continuation": {"from": 0.1, "to": 0.5}}})"),
                  "ca.continuation: missing \"step\"");
  expect_contains(issues_of(R"({"ca": {"continuation": {"from": 0.5, "to": 0.5, "step": 0.1}}})"),
                  "ca.continuation.to");
  expect_contains(issues_of(R"({"ca": {"continuation": {"from": 0, "to": 1, "step": 0.1}}})"),
                  "ca.continuation.from");
  expect_contains(
      issues_of(
          R"({"ca": {"continuation": {"from": 0.1, "to": 1, "step": 0.1, "after_fold": 2.5}}})"),
      "whole number in [0, 1000]");
  expect_contains(
      issues_of(R"({"ca": {"continuation": {"from": 0.1, "to": 1, "step": 0.1, "stpe": 1}}})"),
      "did you mean \"step\"");
  expect_contains(issues_of(R"({"ca": {"continuation": 3}})"), "ca.continuation");
  const ControlOptions at =
      parse_control(
          R"({"ca": {"continuation": {"from": 0.15, "to": 3, "step": 0.05, "at": [0.45, 1.25]}}})")
          .options;
  EXPECT_EQ(at.ca.continuation->at, (std::vector<double>{0.45, 1.25}));
  expect_contains(
      issues_of(
          R"({"ca": {"continuation": {"from": 0.1, "to": 1, "step": 0.1, "at": [0.5, -1]}}})"),
      "ca.continuation.at[1]");
  expect_contains(issues_of(R"({"ca": {"levels": [0.1]}})"), "{\"continuation\": {...}}");
}
