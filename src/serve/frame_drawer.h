// capflow/serve/frame_drawer: what the API asks of whatever draws its images - a state and a
// query in, an encoded image out (serve/frame_service.h draws with capflow's renderer).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "render/snapshot.h"
#include "serve/frame_query.h"

namespace capflow::serve {

struct EncodedFrame {
  std::string bytes;
  std::string content_type;  // image/jpeg or image/png
  double draw_ms = 0, encode_ms = 0;
};

class FrameDrawer {
 public:
  virtual ~FrameDrawer() = default;
  // The image of `s` as `q` asks; nullopt with *error when it cannot be drawn now.
  virtual std::optional<EncodedFrame> draw(std::shared_ptr<const render::Snapshot> s,
                                           const FrameQuery& q, std::string* error) = 0;
};

}  // namespace capflow::serve
