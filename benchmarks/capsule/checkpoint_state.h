// A capsule state from a run's checkpoint, for the study programs of benchmarks/capsule
// (volume_flux, quadrature_study): the newest checkpoint of a run directory, or a .ckpt file;
// its stored control file, the mesh it describes and the node positions.
#pragma once

#include <Eigen/Dense>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "app/simulation.h"
#include "control/control_file.h"
#include "geometry/mesh.h"
#include "output/checkpoint.h"

namespace capflow::study {

struct CheckpointState {
  std::string path;  // the checkpoint file read
  output::Checkpoint ck;
  control::ControlOptions opt;  // the run's control file as stored in the checkpoint
  std::unique_ptr<geometry::Mesh> mesh;
  Eigen::Matrix3Xd x;
};

inline CheckpointState load_checkpoint_state(const std::string& arg) {
  CheckpointState s;
  s.path = arg;
  if (std::filesystem::is_directory(arg)) {
    s.path = app::Simulation::latest_checkpoint(arg);
    if (s.path.empty()) throw std::runtime_error(arg + ": no checkpoint in checkpoints/");
  }
  s.ck = output::Checkpoint::read(s.path);
  s.opt = control::parse_control(s.ck.text("control"), s.path + " (stored control)").options;
  s.mesh = control::make_mesh(s.opt.mesh);
  const long n = s.mesh->num_local();
  const auto& xv = s.ck.doubles("x", 3 * n);
  s.x = Eigen::Map<const Eigen::Matrix3Xd>(xv.data(), 3, n);
  return s;
}

}  // namespace capflow::study
