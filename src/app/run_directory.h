// capflow/app/run_directory: a run directory - its layout, its lock, and every write into it.
//
// Layout (docs/usage.md, "Run directory"):
//   run.lock          held (flock, exclusive) for the run's life; holds the PID of its process
//   control.json      the effective control file          control.source  the watched file
//   timeseries.csv  steady.csv  events.jsonl  run.log      appended whole lines (AppendFile)
//   checkpoints/ckpt_SSSSSSSSSS.ckpt   frames/  profiles/  vtk/  surface.pvd  movie*.mp4
//   preview.png
//
// Opening (RunDirectory::open):
//   Create     a new run: the directory must not exist or be empty (it is created). An existing
//              capflow run is refused (continue it with --resume, or --overwrite it); any other
//              non-empty directory (e.g. "/") is refused, --overwrite or not.
//   Overwrite  as Create, but an existing capflow run is replaced: its files (the names above,
//              nothing else) are removed after the lock is taken.
//   Resume     an existing capflow run.
// A new run whose start fails (before its first checkpoint) calls abandon(): what it wrote is
// removed, and the directory too when it made it.
// In every mode a directory whose lock another process holds is refused, naming its PID. All
// refusals are UserError (exit 2).
//
// Writes: AppendFile writes each record (a CSV row, an event line) with one write(2); a failed
// or short write cuts the file back to its length before the record and throws OutputError
// naming the file, so a file never holds half a row. write_text() replaces a file atomically
// (temporary file, rename). Every failure is an OutputError (exit 5).
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace capflow::app {

// A file opened for appending whole records.
class AppendFile {
 public:
  AppendFile() = default;
  ~AppendFile();
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  // Opens (creating it; `truncate`: emptied first). OutputError on failure.
  void open(const std::filesystem::path& path, bool truncate);
  // Appends `record` whole, or not at all (OutputError naming the file).
  void append(const std::string& record);
  // Keeps the first `lines` lines (a resume cuts the CSVs back to its checkpoint). When what is
  // cut off ends in a torn line (no newline: a write cut short by a crash), it is first saved to
  // `cut_copy` (unless empty). OutputError on failure; UserError when the file has fewer lines
  // (it does not belong to the checkpoint) or is not a regular file.
  void keep_lines(long lines, const std::filesystem::path& cut_copy = {});

  // The whole lines of a record file and whether a torn line follows them (0 and false for a
  // missing file). UserError when it is not a regular file (never blocks on a FIFO).
  struct Lines {
    long whole = 0;
    bool torn = false;
  };
  static Lines count_lines(const std::filesystem::path& path);
  const std::filesystem::path& path() const { return path_; }
  void close();

 private:
  int fd_ = -1;
  std::filesystem::path path_;
};

class RunDirectory {
 public:
  enum class Mode { Create, Overwrite, Resume };

  static std::unique_ptr<RunDirectory> open(const std::filesystem::path& dir, Mode mode);
  ~RunDirectory();  // releases the lock
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  // True when `dir` holds a capflow run (control.json and events.jsonl or checkpoints/).
  static bool is_run(const std::filesystem::path& dir);

  const std::filesystem::path& path() const { return dir_; }
  std::filesystem::path file(const std::string& name) const { return dir_ / name; }

  AppendFile& timeseries() { return timeseries_; }
  AppendFile& steady() { return steady_; }
  AppendFile& events() { return events_; }
  AppendFile& log() { return log_; }
  // Opens the four appended files (`fresh`: emptied, and the CSV headers written).
  void open_records(bool fresh, const std::string& timeseries_header,
                    const std::string& steady_header);

  // Everything written to the run directory's file system on stable storage (OutputError).
  void sync() const;
  // Replaces <dir>/<name> atomically with `text` (OutputError on failure).
  void write_text(const std::string& name, const std::string& text) const;
  // Creates <dir>/<name>/ (OutputError on failure) and returns its path.
  std::filesystem::path subdirectory(const std::string& name) const;

  // checkpoints/ckpt_SSSSSSSSSS.ckpt for a step count; the checkpoint files, newest first.
  std::filesystem::path checkpoint_path(long steps) const;
  static std::vector<std::filesystem::path> checkpoints(const std::filesystem::path& dir);
  // Removes all but the `keep` newest checkpoints (and stale .tmp files).
  void prune_checkpoints(int keep) const;

  // A start that failed before its first checkpoint: removes what this run wrote (the names
  // above, nothing else) and the directory itself when this open created it and it is empty
  // then, so that the same command works once the cause is gone. Never throws.
  void abandon();

 private:
  RunDirectory() = default;
  void lock(Mode mode);
  void remove_run_files() const;

  std::filesystem::path dir_;
  int lock_fd_ = -1;
  bool created_ = false;  // open() made the directory
  AppendFile timeseries_, steady_, events_, log_;
};

}  // namespace capflow::app
