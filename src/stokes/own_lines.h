// capflow/stokes/own_lines: the single layer's own-element lines interpolated across once per
// call. The own rules of all the nodes of an element's column i share their constant-s lines
// (and those of a row j their constant-t lines) in the element's orientation
// (OwnRules::row_bases), so stage 1 (line_sums.h) of an own rule is done per (element,
// direction, node index) for all the targets of a call, instead of per (target, own element):
// at the octant targets of NE=6 NB=10 about 5x fewer stage-1 lines. The rule's symmetry then only
// selects the lines and the sign of the coordinate along them (OwnRules::element_line); the
// single layer's integrand does not depend on the orientation (it uses |x_s x x_t|).
#pragma once

#include <vector>

#include "stokes/line_sums.h"
#include "stokes/own_rules.h"

namespace capflow::stokes {

class OwnLines {
 public:
  // Forgets the marks, for a mesh of ne elements, nb nodes per direction and own rules with
  // ray_nodes ray nodes (OwnRules::ray_nodes() > 0).
  void reset(int ne, int nb, int ray_nodes);
  // The lines of node index i in direction dir (0: constant s, x_i + u (+-1 - x_i); 1: constant
  // t) of element e will be read.
  void need(int e, int dir, int i);
  // The marked (element, direction, node index) triples, the slots 0 .. slots() - 1.
  int slots() const { return slots_; }
  // Sizes the rows of every slot; after the last need, before make.
  void allocate();
  // Stage 1 of slot s from its element's Chebyshev data (ce, as line_sums.h chebyshev_element
  // makes them). Slots may be made concurrently.
  void make(int s, const OwnRules& own, const std::vector<ChebElement>& ce);
  // The number of lines the slots interpolate (for OperatorStats::flops).
  long lines() const { return static_cast<long>(slots_) * 2 * nr_; }
  // The stage-1 rows of line L of an own rule of element e at the node (i, j) (i for dir 0, j
  // for dir 1 is the line's node index).
  LineRows rows(int e, const OwnRules::ElementLine& L, int i, int j) const {
    const int s = slot_[(e * 2 + L.dir) * nb_ + (L.dir == 0 ? i : j)];
    const long line = static_cast<long>(s) * 2 * nr_ + L.side * nr_ + L.q;
    return LineRows{A_.data() + line * ka_, B_.data() + line * kb_, L.along};
  }

 private:
  int nb_ = 0, nr_ = 0, slots_ = 0;
  long ka_ = 0, kb_ = 0;       // columns of the A and B rows
  std::vector<int> slot_;      // (e * 2 + dir) * nb + i -> slot, -1 if not needed
  std::vector<int> key_;       // per slot: its (e * 2 + dir) * nb + i
  std::vector<double> A_, B_;  // per slot: 2 ray_nodes rows, side-major
};

}  // namespace capflow::stokes
