// Runs ffprobe (package ffmpeg) on a movie and parses codec, pixel format, packet count and
// duration. Used by the output and renderer tests.
#pragma once

#include <cstdio>
#include <map>
#include <string>

namespace capflow::testing {

struct ProbeResult {
  bool ok = false;
  std::string codec, pix_fmt, raw;
  long packets = -1;
  int width = 0, height = 0;
  double duration = -1;
};

inline ProbeResult ffprobe(const std::string& path) {
  ProbeResult r;
  const std::string cmd =
      "ffprobe -v error -select_streams v:0 -count_packets -show_entries "
      "stream=codec_name,pix_fmt,nb_read_packets,width,height:format=duration "
      "-of default=nw=1 '" + path + "' 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char line[512];
  std::map<std::string, std::string> kv;
  while (fgets(line, sizeof line, p)) {
    r.raw += line;
    std::string s(line);
    const auto eq = s.find('=');
    if (eq == std::string::npos) continue;
    std::string v = s.substr(eq + 1);
    while (!v.empty() && (v.back() == '\n' || v.back() == '\r')) v.pop_back();
    kv[s.substr(0, eq)] = v;
  }
  r.ok = pclose(p) == 0 && kv.count("codec_name");
  r.codec = kv["codec_name"];
  r.pix_fmt = kv["pix_fmt"];
  if (kv.count("nb_read_packets")) r.packets = std::atol(kv["nb_read_packets"].c_str());
  if (kv.count("width")) r.width = std::atoi(kv["width"].c_str());
  if (kv.count("height")) r.height = std::atoi(kv["height"].c_str());
  if (kv.count("duration") && kv["duration"] != "N/A") r.duration = std::atof(kv["duration"].c_str());
  return r;
}

}  // namespace capflow::testing
