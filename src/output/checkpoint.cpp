#include "output/checkpoint.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

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

  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError("cannot write " + tmp + ": " + std::strerror(errno));
  // A failed write removes the temporary file: no partial checkpoint is left behind.
  auto fail = [&](const std::string& what) {
    const std::string err = std::strerror(errno);
    ::close(fd);
    ::unlink(tmp.c_str());
    throw CheckpointError("cannot write " + path + " (" + what + "): " + err);
  };
  size_t off = 0;
  while (off < b.size()) {
    const ssize_t n = ::write(fd, b.data() + off, b.size() - off);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("write");
    if (n == 0) {
      errno = ENOSPC;
      fail("write");
    }
    off += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0) fail("fsync");
  if (::close(fd) != 0) {
    const std::string err = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw CheckpointError("cannot write " + path + " (close): " + err);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string err = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw CheckpointError("cannot rename " + tmp + " to " + path + ": " + err);
  }
}

Checkpoint Checkpoint::read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError(path + ": cannot open the checkpoint");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string buf = ss.str();
  if (buf.size() < 8 || std::memcmp(buf.data(), kMagic, 8) != 0)
    throw CheckpointError(path + ": not a capflow checkpoint (wrong magic bytes)");
  if (buf.size() < 8 + 4 + 4 + 4 + 8)
    throw CheckpointError(path + ": truncated checkpoint (" + std::to_string(buf.size()) + " bytes)");
  Cursor c{buf, 8, path};
  const uint32_t version = c.get<uint32_t>();
  if (version != kFormatVersion)
    throw CheckpointError(path + ": checkpoint format version " + std::to_string(version) +
                          ", this capflow reads version " + std::to_string(kFormatVersion));
  if (std::memcmp(buf.data() + buf.size() - 8, kEnd, 8) != 0)
    throw CheckpointError(path + ": truncated checkpoint (end marker missing)");
  const size_t body = buf.size() - 12;
  uint32_t stored;
  std::memcpy(&stored, buf.data() + body, 4);
  const uint32_t crc = static_cast<uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(buf.data()), static_cast<uInt>(body)));
  if (crc != stored) throw CheckpointError(path + ": corrupt checkpoint (checksum mismatch)");
  Checkpoint cp;
  cp.source = path;
  const uint32_t count = c.get<uint32_t>();
  for (uint32_t r = 0; r < count; ++r) {
    const uint32_t len = c.get<uint32_t>();
    c.need(len);
    const std::string name = buf.substr(c.pos, len);
    c.pos += len;
    const uint8_t type = c.get<uint8_t>();
    const uint64_t n = c.get<uint64_t>();
    if (n > body) throw CheckpointError(path + ": malformed checkpoint record \"" + name + "\"");
    if (type == 1) {
      c.need(n * sizeof(double));
      std::vector<double> v(n);
      std::memcpy(v.data(), buf.data() + c.pos, n * sizeof(double));
      c.pos += n * sizeof(double);
      cp.f64_[name] = std::move(v);
    } else if (type == 2) {
      c.need(n * sizeof(int64_t));
      std::vector<int64_t> v(n);
      std::memcpy(v.data(), buf.data() + c.pos, n * sizeof(int64_t));
      c.pos += n * sizeof(int64_t);
      cp.i64_[name] = std::move(v);
    } else if (type == 3) {
      c.need(n);
      cp.str_[name] = buf.substr(c.pos, n);
      c.pos += n;
    } else {
      throw CheckpointError(path + ": malformed checkpoint record \"" + name + "\" (type " +
                            std::to_string(type) + ")");
    }
  }
  if (c.pos != body) throw CheckpointError(path + ": malformed checkpoint (trailing bytes)");
  return cp;
}

}  // namespace capflow::output
