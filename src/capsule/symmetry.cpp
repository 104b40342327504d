#include "capsule/symmetry.h"

#include <map>

namespace capflow::capsule {

SymmetryMap::SymmetryMap(const geometry::Mesh& mesh, SymmetryKind kind) : kind_(kind) {
  const int n = mesh.num_local();
  const auto& ref = mesh.reference();
  constexpr double tol = 1e-12;
  source_.assign(n, -1);
  sign_.assign(n, Eigen::Vector3d::Ones());
  std::map<int, int> target_of_class;  // coincidence class -> index in targets_
  for (int m = 0; m < n; ++m) {
    int r = m;
    Eigen::Vector3d s = Eigen::Vector3d::Ones();
    if (kind == SymmetryKind::Octant) {
      for (int k = 0; k < 3; ++k)
        if (ref(k, m) < -tol) {
          r = mesh.mirror(k)[r];
          s[k] = -s[k];
        }
    } else if (kind == SymmetryKind::Shear) {
      if (ref(1, m) < -tol) {
        r = mesh.mirror(1)[r];
        s[1] = -1;
      }
      const double xr = ref(0, r), zr = ref(2, r);
      if (xr < -tol || (xr <= tol && zr < -tol)) {  // point reflection (x,z) -> (-x,-z)
        r = mesh.mirror(2)[mesh.mirror(0)[r]];
        s[0] = -s[0];
        s[2] = -s[2];
      }
    }
    const int cls = mesh.unique_of()[r];
    auto it = target_of_class.find(cls);
    if (it == target_of_class.end()) {
      it = target_of_class.emplace(cls, static_cast<int>(targets_.size())).first;
      targets_.push_back(r);
    }
    source_[m] = it->second;
    sign_[m] = s;
  }
}

void SymmetryMap::expand(const Eigen::Matrix3Xd& at_targets, Eigen::Matrix3Xd* all) const {
  const int n = static_cast<int>(source_.size());
  all->resize(3, n);
  for (int m = 0; m < n; ++m) all->col(m) = at_targets.col(source_[m]).cwiseProduct(sign_[m]);
}

stokes::NodeExpansion SymmetryMap::expansion() const {
  stokes::NodeExpansion ex;
  ex.columns = static_cast<int>(targets_.size());
  ex.column = source_;
  ex.sign = sign_;
  return ex;
}

}  // namespace capflow::capsule
