#include "output/checkpoint.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "files/atomic_write.h"
#include "files/input_file.h"
#include "files/printable.h"

namespace capflow::output {

namespace {
constexpr char kMagic[8] = {'C', 'A', 'P', 'F', 'L', 'O', 'W', 'C'};
constexpr char kEnd[8] = {'C', 'K', 'P', 'T', 'E', 'N', 'D', '\0'};

template <class T>
void put_raw(std::string* b, const T& v) {
  b->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

struct Cursor {
  const std::string& buf;
  size_t pos;
  const std::string& file;
  void need(size_t n) const {
    if (pos + n > buf.size())
      throw CheckpointError(file + ": truncated or malformed checkpoint (record runs past the end)");
  }
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, buf.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
};
}  // namespace

const std::vector<double>& Checkpoint::doubles(const std::string& name, long expect) const {
  auto it = f64_.find(name);
  if (it == f64_.end()) throw CheckpointError(source + ": checkpoint has no field \"" + name + "\"");
  if (expect >= 0 && static_cast<long>(it->second.size()) != expect)
    throw CheckpointError(source + ": checkpoint field \"" + name + "\" has " +
                          std::to_string(it->second.size()) + " values, expected " +
                          std::to_string(expect));
  return it->second;
}

const std::vector<int64_t>& Checkpoint::ints(const std::string& name, long expect) const {
  auto it = i64_.find(name);
  if (it == i64_.end()) throw CheckpointError(source + ": checkpoint has no field \"" + name + "\"");
  if (expect >= 0 && static_cast<long>(it->second.size()) != expect)
    throw CheckpointError(source + ": checkpoint field \"" + name + "\" has " +
                          std::to_string(it->second.size()) + " values, expected " +
                          std::to_string(expect));
  return it->second;
}

const std::string& Checkpoint::text(const std::string& name) const {
  auto it = str_.find(name);
  if (it == str_.end()) throw CheckpointError(source + ": checkpoint has no field \"" + name + "\"");
  return it->second;
}

void Checkpoint::write(const std::string& path) const {
  std::string b(kMagic, 8);
  put_raw(&b, kFormatVersion);
  put_raw(&b, static_cast<uint32_t>(f64_.size() + i64_.size() + str_.size()));
  auto header = [&b](const std::string& name, uint8_t type, uint64_t count) {
    put_raw(&b, static_cast<uint32_t>(name.size()));
    b += name;
    put_raw(&b, type);
    put_raw(&b, count);
  };
  for (const auto& [name, v] : f64_) {
    header(name, 1, v.size());
    b.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  }
  for (const auto& [name, v] : i64_) {
    header(name, 2, v.size());
    b.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(int64_t));
  }
  for (const auto& [name, v] : str_) {
    header(name, 3, v.size());
    b += v;
  }
  const uint32_t crc = static_cast<uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(b.data()), static_cast<uInt>(b.size())));
  put_raw(&b, crc);
  b.append(kEnd, 8);

  try {
    files::write_atomically(path, b, {/*sync=*/true, /*unique_temp=*/false});
  } catch (const files::WriteError& e) {
    throw CheckpointError(e.what());
  }
}

namespace {

// The first 12 bytes: magic and format version.
void check_header(const std::string& head, std::size_t size, const std::string& name) {
  if (head.size() < 8 || std::memcmp(head.data(), kMagic, 8) != 0)
    throw CheckpointError(name + ": not a capflow checkpoint (wrong magic bytes)");
  if (head.size() < 12 || size < 8 + 4 + 4 + 4 + 8)
    throw CheckpointError(name + ": truncated checkpoint (" + std::to_string(size) + " bytes)");
  uint32_t version;
  std::memcpy(&version, head.data() + 8, 4);
  if (version != Checkpoint::kFormatVersion)
    throw CheckpointError(name + ": checkpoint format version " + std::to_string(version) +
                          ", this capflow reads version " +
                          std::to_string(Checkpoint::kFormatVersion));
}

}  // namespace

Checkpoint Checkpoint::read(const std::string& path) {
  std::string buf;
  try {
    // The header first: a file that is not a checkpoint is refused without reading its body.
    files::InputFile in(path, "checkpoint", kMaxBytes);
    check_header(in.read_prefix(12), in.size(), files::printable(path));
    buf = in.read_all();
  } catch (const files::InputError& e) {
    throw CheckpointError(e.what());
  }
  return parse(buf, path);
}

Checkpoint Checkpoint::parse(const std::string& buf, const std::string& path) {
  const std::string name = files::printable(path);
  check_header(buf.substr(0, 12), buf.size(), name);
  if (buf.size() < 8 + 4 + 4 + 4 + 8)
    throw CheckpointError(name + ": truncated checkpoint (" + std::to_string(buf.size()) + " bytes)");
  if (std::memcmp(buf.data() + buf.size() - 8, kEnd, 8) != 0)
    throw CheckpointError(name + ": truncated checkpoint (end marker missing)");
  const size_t body = buf.size() - 12;
  uint32_t stored;
  std::memcpy(&stored, buf.data() + body, 4);
  const uint32_t crc = static_cast<uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(buf.data()), static_cast<uInt>(body)));
  if (crc != stored) throw CheckpointError(name + ": corrupt checkpoint (checksum mismatch)");
  Checkpoint cp;
  cp.source = path;
  Cursor c{buf, 12, name};
  const uint32_t count = c.get<uint32_t>();
  for (uint32_t r = 0; r < count; ++r) {
    const uint32_t len = c.get<uint32_t>();
    c.need(len);
    const std::string field = buf.substr(c.pos, len);
    const std::string shown = files::printable(field, 64);
    c.pos += len;
    const uint8_t type = c.get<uint8_t>();
    const uint64_t n = c.get<uint64_t>();
    if (n > body) throw CheckpointError(name + ": malformed checkpoint record \"" + shown + "\"");
    if (type == 1) {
      c.need(n * sizeof(double));
      std::vector<double> v(n);
      if (n > 0) std::memcpy(v.data(), buf.data() + c.pos, n * sizeof(double));
      c.pos += n * sizeof(double);
      cp.f64_[field] = std::move(v);
    } else if (type == 2) {
      c.need(n * sizeof(int64_t));
      std::vector<int64_t> v(n);
      if (n > 0) std::memcpy(v.data(), buf.data() + c.pos, n * sizeof(int64_t));
      c.pos += n * sizeof(int64_t);
      cp.i64_[field] = std::move(v);
    } else if (type == 3) {
      c.need(n);
      cp.str_[field] = buf.substr(c.pos, n);
      c.pos += n;
    } else {
      throw CheckpointError(name + ": malformed checkpoint record \"" + shown + "\" (type " +
                            std::to_string(type) + ")");
    }
  }
  if (c.pos != body) throw CheckpointError(name + ": malformed checkpoint (trailing bytes)");
  return cp;
}

}  // namespace capflow::output
