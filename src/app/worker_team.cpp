#include "app/worker_team.h"

#include <csignal>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "control/control_file.h"
#include "parallel/team.h"

namespace capflow::app {

namespace {

enum Op : int { kEnd = 0, kSetUp = 1, kSingleLayer = 2, kDoubleLayerMatrix = 3, kReset = 4 };

int g_next_id = 0;
bool g_ended = false;

// This rank's positions among n targets: rank, rank + size, rank + 2 size, ... (every size-th:
// the dear edge and corner targets spread evenly).
std::vector<int> my_positions(int n) {
  std::vector<int> mine;
  for (int k = parallel::rank(); k < n; k += parallel::size()) mine.push_back(k);
  return mine;
}

// The target positions in the order the gather concatenates the ranks' shares.
std::vector<int> gathered_order(int n, int size) {
  std::vector<int> order;
  for (int r = 0; r < size; ++r)
    for (int k = r; k < n; k += size) order.push_back(k);
  return order;
}

// This rank's share of SL[f] at targets (my_positions), as 3 x share values.
std::vector<double> my_share(const stokes::BoundaryOperators& ops, const Eigen::Matrix3Xd& x,
                             const Eigen::Matrix3Xd& f, const std::vector<int>& targets) {
  std::vector<int> mine;
  for (int k : my_positions(static_cast<int>(targets.size())))
    mine.push_back(targets[static_cast<size_t>(k)]);
  Eigen::Matrix3Xd out(3, static_cast<long>(mine.size()));
  if (!mine.empty()) ops.single_layer(x, f, mine, out);
  return std::vector<double>(out.data(), out.data() + out.size());
}

// This rank's rows of the viscosity-ratio solve's double-layer matrix: the rows of the same
// targets as my_share, flattened row-major (3 share x 3 targets values).
std::vector<double> my_rows(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, bool symmetry,
                            int targets) {
  const std::vector<int> mine = my_positions(targets);
  if (mine.empty()) return {};
  const stokes::RowMat rows = cap.double_layer_rows(x, symmetry, mine);
  return std::vector<double>(rows.data(), rows.data() + rows.size());
}

// The ranks' rows gathered in rank order back in target order (3 targets x 3 targets).
stokes::RowMat interleave_rows(const std::vector<double>& all, int targets, int size) {
  const long n = 3L * targets;
  if (static_cast<long>(all.size()) != n * n)
    parallel::abort_all("the ranks' double-layer rows: " + std::to_string(all.size()) +
                            " values for a " + std::to_string(n) + " x " + std::to_string(n) +
                            " matrix",
                        3);
  stokes::RowMat out(n, n);
  size_t at = 0;
  for (int k : gathered_order(targets, size))
    for (int i = 0; i < 3; ++i, at += static_cast<size_t>(n))
      out.row(3L * k + i) = Eigen::Map<const Eigen::RowVectorXd>(all.data() + at, n);
  return out;
}

// The shares gathered in rank order back in target order (3 x targets).
Eigen::Matrix3Xd interleave(const std::vector<double>& all, size_t n, int size) {
  Eigen::Matrix3Xd out(3, static_cast<long>(n));
  size_t at = 0;
  for (int k : gathered_order(static_cast<int>(n), size)) {
    out.col(k) = Eigen::Vector3d(all[at], all[at + 1], all[at + 2]);
    at += 3;
  }
  return out;
}

std::vector<double> flat(const Eigen::Matrix3Xd& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

Eigen::Matrix3Xd matrix(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::Matrix3Xd>(v.data(), 3, static_cast<long>(v.size() / 3));
}

}  // namespace

void attach_team(capsule::Capsule& cap, const control::ControlOptions& options) {
  if (parallel::size() <= 1 || parallel::rank() != 0) return;
  int op = kSetUp, id = g_next_id++;
  std::string text = control::to_json_text(options);
  parallel::broadcast(&op);
  parallel::broadcast(&id);
  parallel::broadcast(&text);
  const stokes::BoundaryOperators* ops = &cap.operators();
  cap.set_single_layer([ops, id](const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& f,
                                 const std::vector<int>& targets, Eigen::Matrix3Xd& out) {
    int o = kSingleLayer, i = id;
    std::vector<double> xs = flat(x), fs = flat(f);
    std::vector<int> ts = targets;
    parallel::broadcast(&o);
    parallel::broadcast(&i);
    parallel::broadcast(&xs);
    parallel::broadcast(&fs);
    parallel::broadcast(&ts);
    out = interleave(parallel::gather(my_share(*ops, x, f, targets)), targets.size(),
                     parallel::size());
  });
  if (options.viscosity_ratio == 1.0) return;
  const capsule::Capsule* c = &cap;
  cap.set_double_layer_matrix([c, id](const Eigen::Matrix3Xd& x, bool symmetry) {
    int o = kDoubleLayerMatrix, i = id, sym = symmetry ? 1 : 0;
    int targets = static_cast<int>(c->symmetry_targets(symmetry));
    std::vector<double> xs = flat(x);
    parallel::broadcast(&o);
    parallel::broadcast(&i);
    parallel::broadcast(&xs);
    parallel::broadcast(&sym);
    parallel::broadcast(&targets);
    return interleave_rows(parallel::gather(my_rows(*c, x, symmetry, targets)), targets,
                           parallel::size());
  });
}

void reset_workers() {
  if (parallel::size() <= 1 || parallel::rank() != 0 || g_ended) return;
  int op = kReset, id = 0;
  parallel::broadcast(&op);
  parallel::broadcast(&id);
}

void end_workers() {
  if (parallel::size() <= 1 || parallel::rank() != 0 || g_ended) return;
  g_ended = true;
  int op = kEnd;
  parallel::broadcast(&op);
}

int serve_team() {
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  std::signal(SIGHUP, SIG_IGN);
  struct Built {
    std::unique_ptr<geometry::Mesh> mesh;
    std::unique_ptr<capsule::Capsule> cap;
  };
  std::map<int, Built> built;
  while (true) {
    int op = kEnd, id = 0;
    parallel::broadcast(&op);
    if (op == kEnd) return 0;
    parallel::broadcast(&id);
    try {
      if (op == kSetUp) {
        std::string text;
        parallel::broadcast(&text);
        const control::ControlOptions o = control::parse_control(text, "rank 0's control").options;
        Built b;
        b.mesh = control::make_mesh(o.mesh);
        b.cap = std::make_unique<capsule::Capsule>(*b.mesh, o.law, o.flow,
                                                   control::dynamics_options(o));
        built[id] = std::move(b);
      } else if (op == kSingleLayer) {
        std::vector<double> xs, fs;
        std::vector<int> targets;
        parallel::broadcast(&xs);
        parallel::broadcast(&fs);
        parallel::broadcast(&targets);
        const auto it = built.find(id);
        if (it == built.end()) parallel::abort_all("no capsule " + std::to_string(id), 3);
        parallel::gather(my_share(it->second.cap->operators(), matrix(xs), matrix(fs), targets));
      } else if (op == kReset) {
        built.clear();
      } else if (op == kDoubleLayerMatrix) {
        std::vector<double> xs;
        int sym = 1, targets = 0;
        parallel::broadcast(&xs);
        parallel::broadcast(&sym);
        parallel::broadcast(&targets);
        const auto it = built.find(id);
        if (it == built.end()) parallel::abort_all("no capsule " + std::to_string(id), 3);
        parallel::gather(my_rows(*it->second.cap, matrix(xs), sym != 0, targets));
      } else {
        parallel::abort_all("unknown request " + std::to_string(op), 3);
      }
    } catch (const std::exception& e) {
      parallel::abort_all(e.what(), 3);
    }
  }
}

}  // namespace capflow::app
