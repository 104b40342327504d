// capflow/render/snapshot_queue: the one queue between the simulation thread (producer) and
// the renderer thread (consumer).
//
// Two lanes:
//  * Movie lane: bounded FIFO of `capacity` snapshots (>= 1). push_frame() BLOCKS while the
//    lane is full: a slow renderer slows the solver down (back-pressure), so no movie frame is
//    ever dropped. Frames come out in push order.
//  * Preview lane: a single slot holding only the LATEST snapshot. offer_preview() never waits
//    for the consumer: it replaces whatever preview is pending (the replaced one is dropped).
// pop() blocks until something is available and prefers movie frames (FIFO) over the preview.
//
// Stop semantics: close() wakes everybody. After close(), push_frame()/offer_preview() return
// false without queuing; pop() still hands out every movie frame queued before close() and
// then returns std::nullopt (a pending preview is discarded). close() is idempotent.
// All member functions are thread-safe; snapshots are moved in and out (the queue owns them).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <optional>
#include <deque>
#include <stdexcept>
#include <utility>

#include "render/snapshot.h"

namespace capflow::render {

class SnapshotQueue {
 public:
  enum class Lane { Movie, Preview };
  struct Item {
    Lane lane;
    Snapshot snapshot;
  };

  explicit SnapshotQueue(std::size_t capacity) : capacity_(capacity) {
    if (capacity == 0) throw std::invalid_argument("SnapshotQueue: capacity must be >= 1");
  }

  // Blocks while the movie lane is full. Returns false (snapshot not queued) once closed.
  bool push_frame(Snapshot s) {
    std::unique_lock<std::mutex> lock(mu_);
    if (!closed_ && frames_.size() >= capacity_) {
      ++producer_waits_;
      not_full_.wait(lock, [&] { return closed_ || frames_.size() < capacity_; });
    }
    if (closed_) return false;
    frames_.push_back(std::move(s));
    not_empty_.notify_one();
    return true;
  }

  // Never waits for the consumer. Returns false once closed.
  bool offer_preview(Snapshot s) {
    std::lock_guard<std::mutex> lock(mu_);
    if (closed_) return false;
    if (preview_) ++previews_replaced_;
    preview_ = std::move(s);
    not_empty_.notify_one();
    return true;
  }

  // Blocks until an item is available; nullopt when closed and the movie lane is drained.
  std::optional<Item> pop() {
    std::unique_lock<std::mutex> lock(mu_);
    if (!closed_ && frames_.empty() && !preview_) {
      ++consumer_waits_;
      not_empty_.wait(lock, [&] { return closed_ || !frames_.empty() || preview_; });
    }
    if (!frames_.empty()) {
      Item it{Lane::Movie, std::move(frames_.front())};
      frames_.pop_front();
      not_full_.notify_one();
      return it;
    }
    if (closed_) {
      preview_.reset();
      return std::nullopt;
    }
    Item it{Lane::Preview, std::move(*preview_)};
    preview_.reset();
    return it;
  }

  void close() {
    std::lock_guard<std::mutex> lock(mu_);
    closed_ = true;
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  std::size_t capacity() const { return capacity_; }
  std::size_t frames_queued() const { std::lock_guard<std::mutex> l(mu_); return frames_.size(); }
  bool closed() const { std::lock_guard<std::mutex> l(mu_); return closed_; }
  // Times push_frame() had to wait (back-pressure events).
  long producer_waits() const { std::lock_guard<std::mutex> l(mu_); return producer_waits_; }
  // Times pop() had to wait for an item (the renderer idle).
  long consumer_waits() const { std::lock_guard<std::mutex> l(mu_); return consumer_waits_; }
  // Previews dropped because a newer one replaced them before the consumer took them.
  long previews_replaced() const { std::lock_guard<std::mutex> l(mu_); return previews_replaced_; }

 private:
  const std::size_t capacity_;
  mutable std::mutex mu_;
  std::condition_variable not_full_, not_empty_;
  std::deque<Snapshot> frames_;
  std::optional<Snapshot> preview_;
  bool closed_ = false;
  long producer_waits_ = 0;
  long consumer_waits_ = 0;
  long previews_replaced_ = 0;
};

}  // namespace capflow::render
