// capflow/figures/labels: axis labels and legend entries as gnuplot enhanced text, every
// quantity with its symbol (italic) and its unit, in capflow's scales: lengths in units of the
// unstressed radius a, times of the inverse flow rate 1/G, tensions of the shear modulus G_s.
#pragma once

#include <string>

namespace capflow::figures::labels {

// Literal text in enhanced mode (run labels, file names): the markup characters escaped.
std::string literal(const std::string& s);
// An italic symbol: "{/:Italic s}".
std::string it(const std::string& s);

// Axis labels ("quantity / unit").
std::string time();                 // t / G^{−1}
std::string deformation();          // D
std::string half_lengths();         // L, S, W / a
std::string capillary();            // Ca
std::string tension();              // τ / G_s
std::string curvature();            // edge curvature κ / a^{−1}
std::string volume_drift();         // V / V_0 − 1
std::string inclination();          // θ / deg
std::string area();                 // A / a^2
std::string coordinate(char axis);  // x / a

}  // namespace capflow::figures::labels
