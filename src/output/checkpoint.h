// capflow/output/checkpoint: a versioned, checksummed binary container of named arrays, written
// atomically. It knows nothing of the solver: the run driver decides what goes in.
//
// File layout (little-endian):
//   "CAPFLOWC" | u32 format version (kFormatVersion) | u32 record count |
//   records: u32 name length, name, u8 type (1 f64, 2 i64, 3 string), u64 count, payload |
//   u32 CRC-32 (zlib) of everything before it | "CKPTEND\0"
// Doubles are stored bit for bit, so a restart continues exactly.
// write() writes <path>.tmp, fsyncs it and renames it over <path>: a crash never leaves a
// half-written checkpoint under the final name, and a failed write (disk full) removes the
// temporary file and throws CheckpointError naming the file.
// read() follows files/input_file.h's rule (a regular file, at most kMaxBytes, never blocking)
// and checks the header (magic, version) before it reads the body. It refuses, with a message
// naming the file: a special or too large file, a foreign file (bad magic), another format
// version, a truncated file, a checksum mismatch, or malformed records.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace capflow::output {

struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Checkpoint {
 public:
  static constexpr uint32_t kFormatVersion = 1;
  // The largest checkpoint read (NE=14, NB=24 writes about 1 MiB).
  static constexpr std::size_t kMaxBytes = std::size_t{64} << 20;

  void put(const std::string& name, std::vector<double> v) { f64_[name] = std::move(v); }
  void put(const std::string& name, std::vector<int64_t> v) { i64_[name] = std::move(v); }
  void put(const std::string& name, std::string v) { str_[name] = std::move(v); }
  void put_scalar(const std::string& name, double v) { put(name, std::vector<double>{v}); }
  void put_int(const std::string& name, int64_t v) { put(name, std::vector<int64_t>{v}); }

  bool has(const std::string& name) const {
    return f64_.count(name) || i64_.count(name) || str_.count(name);
  }
  // Accessors throw CheckpointError naming the missing field (or a wrong size when `expect`
  // is given).
  const std::vector<double>& doubles(const std::string& name, long expect = -1) const;
  const std::vector<int64_t>& ints(const std::string& name, long expect = -1) const;
  const std::string& text(const std::string& name) const;
  double scalar(const std::string& name) const { return doubles(name, 1)[0]; }
  int64_t integer(const std::string& name) const { return ints(name, 1)[0]; }

  void write(const std::string& path) const;
  static Checkpoint read(const std::string& path);
  // The same checks on bytes in memory; `path` names them in messages.
  static Checkpoint parse(const std::string& bytes, const std::string& path);

  std::string source;  // the file read from (for messages)

 private:
  std::map<std::string, std::vector<double>> f64_;
  std::map<std::string, std::vector<int64_t>> i64_;
  std::map<std::string, std::string> str_;
};

}  // namespace capflow::output
