#include "stokes/own_lines.h"

namespace capflow::stokes {

void OwnLines::reset(int ne, int nb, int ray_nodes) {
  nb_ = nb;
  nr_ = ray_nodes;
  slots_ = 0;
  ka_ = (6 * nb + 7) & ~7;  // the padded columns of stage 1 (line_sums.cpp pad8)
  kb_ = (3 * nb + 7) & ~7;
  slot_.assign(static_cast<size_t>(ne) * 2 * nb, -1);
  key_.clear();
}

void OwnLines::need(int e, int dir, int i) {
  const int key = (e * 2 + dir) * nb_ + i;
  if (slot_[key] >= 0) return;
  slot_[key] = slots_++;
  key_.push_back(key);
}

void OwnLines::allocate() {
  const long rows = static_cast<long>(slots_) * 2 * nr_;
  if (static_cast<long>(A_.size()) < rows * ka_) A_.resize(rows * ka_);
  if (static_cast<long>(B_.size()) < rows * kb_) B_.resize(rows * kb_);
}

void OwnLines::make(int s, const OwnRules& own, const std::vector<ChebElement>& ce) {
  const int key = key_[s], i = key % nb_, dir = (key / nb_) % 2, e = key / (2 * nb_);
  const long line = static_cast<long>(s) * 2 * nr_;
  single_across(nb_, 2 * nr_, own.row_bases(i).data(), own.row_derivs(i).data(),
                dir == 0 ? ce[e].cs : ce[e].ct, A_.data() + line * ka_, ka_, B_.data() + line * kb_,
                kb_);
}

}  // namespace capflow::stokes
