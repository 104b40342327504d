// stokes/thread_buffers: a boundary-operator call on threads whose buffers were prepared needs no
// loader lock, so it runs while another thread is inside dlopen (the renderer loading its GL
// driver); a thread that was not prepared waits for the dlopen (the control).
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <future>
#include <string>
#include <thread>

#include "geometry/mesh.h"
#include "stokes/boundary_integral.h"
#include "stokes/thread_buffers.h"

using namespace capflow;
using Eigen::Matrix3Xd;

namespace {

// A thread inside dlopen of the held_loader_lock library, its constructor waiting; release()
// lets it finish.
class HeldDlopen {
 public:
  HeldDlopen() {
    if (pipe(started_) != 0 || pipe(release_) != 0) throw std::runtime_error("pipe");
    setenv("CAPFLOW_TEST_CTOR_STARTED", std::to_string(started_[1]).c_str(), 1);
    setenv("CAPFLOW_TEST_CTOR_RELEASE", std::to_string(release_[0]).c_str(), 1);
    thread_ = std::thread([] { handle_ = dlopen(CAPFLOW_HELD_LOADER_LOCK_LIB, RTLD_NOW); });
    char c;
    if (read(started_[0], &c, 1) != 1) throw std::runtime_error("the constructor did not start");
  }
  void release() {
    if (released_) return;
    released_ = true;
    char c = 1;
    if (write(release_[1], &c, 1) != 1) std::abort();
    thread_.join();
  }
  ~HeldDlopen() {
    release();
    for (int fd : {started_[0], started_[1], release_[0], release_[1]}) close(fd);
  }
  static void* handle_;

 private:
  int started_[2], release_[2];
  bool released_ = false;
  std::thread thread_;
};
void* HeldDlopen::handle_ = nullptr;

}  // namespace

TEST(ThreadBuffers, PreparedThreadsCallTheOperatorWhileAnotherThreadIsInDlopen) {
  geometry::Mesh mesh(6, 6);
  const stokes::BoundaryOperators op(mesh);
  const Matrix3Xd& x = mesh.reference();
  const Matrix3Xd f = Matrix3Xd::Ones(3, mesh.num_local());
  const int team = 2;
  // the prepared call runs in a thread of its own (its team: it and one more), prepared first
  std::promise<void> prepared;
  std::promise<Matrix3Xd> result;
  std::promise<void> go;
  std::thread caller([&] {
    omp_set_num_threads(team);
    stokes::prepare_thread_buffers(team);
    prepared.set_value();
    go.get_future().wait();
    result.set_value(op.single_layer(x, f));
  });
  prepared.get_future().wait();
  {
    HeldDlopen held;
    go.set_value();
    std::future<Matrix3Xd> r = result.get_future();
    // Not a timing: without the preparation the call cannot finish before release() below.
    const bool done = r.wait_for(std::chrono::seconds(60)) == std::future_status::ready;
    // the control: a fresh thread's first operator call registers its buffers under the lock
    std::atomic<bool> control_done{false};
    std::thread fresh([&] {
      omp_set_num_threads(1);
      op.single_layer(x, f);
      control_done = true;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const bool control_finished_while_held = control_done;
    held.release();
    fresh.join();
    caller.join();
    EXPECT_TRUE(done) << "the prepared call waited for the dlopen";
    EXPECT_FALSE(control_finished_while_held)
        << "an unprepared thread no longer waits for the loader lock: the preparation is moot";
    if (done) {
      EXPECT_GT(r.get().norm(), 0.0);
    }
  }
  ASSERT_NE(HeldDlopen::handle_, nullptr) << dlerror();
  dlclose(HeldDlopen::handle_);
}
