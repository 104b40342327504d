// SnapshotQueue: back-pressure, FIFO, latest-only preview, stop semantics.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "render/snapshot_queue.h"

namespace capflow::render {
namespace {
// Returns once `done` holds (the other thread reached the state the test needs): a
// synchronisation, not a timed guess; ctest's timeout ends a test that never gets there.
template <class F>
void wait_until(F done) {
  while (!done()) std::this_thread::yield();
}

Snapshot tagged(long k) {
  Snapshot s;
  s.frame = k;
  return s;
}

TEST(SnapshotQueue, PushBlocksWhenFullAndFramesKeepOrder) {
  SnapshotQueue q(2);
  std::atomic<int> pushed{0};
  std::thread producer([&] {
    for (long k = 0; k < 5; ++k) {
      ASSERT_TRUE(q.push_frame(tagged(k)));
      ++pushed;
    }
  });
  wait_until([&] { return q.producer_waits() == 1; });  // the third push waits
  EXPECT_EQ(pushed.load(), 2);  // capacity reached: the producer waits (back-pressure)
  for (long k = 0; k < 5; ++k) {
    auto it = q.pop();
    ASSERT_TRUE(it);
    EXPECT_EQ(it->lane, SnapshotQueue::Lane::Movie);
    EXPECT_EQ(it->snapshot.frame, k);  // nothing dropped, FIFO
  }
  producer.join();
  EXPECT_GE(q.producer_waits(), 1);
}

TEST(SnapshotQueue, PreviewKeepsOnlyLatestAndNeverBlocks) {
  SnapshotQueue q(1);
  ASSERT_TRUE(q.push_frame(tagged(0)));  // movie lane full
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 100; k < 110; ++k) EXPECT_TRUE(q.offer_preview(tagged(k)));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(50));
  EXPECT_EQ(q.previews_replaced(), 9);
  auto a = q.pop();  // movie frames first
  EXPECT_EQ(a->lane, SnapshotQueue::Lane::Movie);
  auto b = q.pop();
  EXPECT_EQ(b->lane, SnapshotQueue::Lane::Preview);
  EXPECT_EQ(b->snapshot.frame, 109);
}

TEST(SnapshotQueue, CloseDrainsQueuedFramesThenStops) {
  SnapshotQueue q(4);
  for (long k = 0; k < 3; ++k) ASSERT_TRUE(q.push_frame(tagged(k)));
  q.offer_preview(tagged(99));
  q.close();
  EXPECT_FALSE(q.push_frame(tagged(7)));
  EXPECT_FALSE(q.offer_preview(tagged(8)));
  for (long k = 0; k < 3; ++k) EXPECT_EQ(q.pop()->snapshot.frame, k);
  EXPECT_FALSE(q.pop());  // pending preview discarded, consumer exits
}

TEST(SnapshotQueue, CloseWakesBlockedProducerAndConsumer) {
  SnapshotQueue q(1);
  ASSERT_TRUE(q.push_frame(tagged(0)));
  std::atomic<int> result{-1};
  std::thread producer([&] { result = q.push_frame(tagged(1)) ? 1 : 0; });
  wait_until([&] { return q.producer_waits() == 1; });  // blocked on the full lane
  q.close();
  producer.join();
  EXPECT_EQ(result.load(), 0);
  SnapshotQueue empty(1);
  std::thread consumer([&] { EXPECT_FALSE(empty.pop()); });
  wait_until([&] { return empty.consumer_waits() == 1; });  // blocked on the empty queue
  empty.close();
  consumer.join();
}

}  // namespace
}  // namespace capflow::render
