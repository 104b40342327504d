#include "membrane/law.h"

#include <cmath>
#include <stdexcept>

namespace capflow::membrane {

EnergyDerivatives SkalakLaw::unit_energy(double i1, double i2) const {
  EnergyDerivatives d;
  d.w = 0.25 * (i1 * i1 + 2.0 * i1 - 2.0 * i2 + c_ * i2 * i2);
  d.w1 = 0.5 * (i1 + 1.0);
  d.w2 = 0.5 * (c_ * i2 - 1.0);
  return d;
}

double SkalakLaw::unit_principal_tension(double l1, double l2) const {
  const double j = l1 * l2;
  return (l1 / l2) * (l1 * l1 - 1.0 + c_ * l2 * l2 * (j * j - 1.0));
}

EnergyDerivatives NeoHookeanLaw::unit_energy(double i1, double i2) const {
  const double r = 1.0 / (i2 + 1.0);
  EnergyDerivatives d;
  d.w = 0.5 * (i1 - 1.0 + r);
  d.w1 = 0.5;
  d.w2 = -0.5 * r * r;
  return d;
}

double NeoHookeanLaw::unit_principal_tension(double l1, double l2) const {
  const double j = l1 * l2;
  return (l1 * l1 - 1.0 / (j * j)) / j;
}

EnergyDerivatives MooneyRivlinLaw::unit_energy(double i1, double i2) const {
  const double r = 1.0 / (i2 + 1.0);
  const double q = 1.0 - psi_;
  EnergyDerivatives d;
  d.w = 0.5 * psi_ * (i1 - 1.0 + r) + 0.5 * q * ((i1 + 2.0) * r + i2 - 2.0);
  d.w1 = 0.5 * psi_ + 0.5 * q * r;
  d.w2 = -0.5 * psi_ * r * r + 0.5 * q * (1.0 - (i1 + 2.0) * r * r);
  return d;
}

double MooneyRivlinLaw::unit_principal_tension(double l1, double l2) const {
  const double j = l1 * l2;
  return (l1 * l1 - 1.0 / (j * j)) / j * (psi_ + l2 * l2 * (1.0 - psi_));
}

bool LawOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!(std::isfinite(gs) && gs > 0)) return fail("membrane law: gs must be finite and > 0");
  if (kind == LawKind::Skalak && !(std::isfinite(c) && c > -0.5))
    return fail("membrane law: Skalak c must be finite and > -1/2 (area modulus 1+2c > 0)");
  if (kind == LawKind::MooneyRivlin && !(psi >= 0.0 && psi <= 1.0))
    return fail("membrane law: Mooney-Rivlin psi must lie in [0, 1]");
  return true;
}

bool parse_law_kind(const std::string& name, LawKind* kind) {
  if (name == "skalak") {
    *kind = LawKind::Skalak;
  } else if (name == "neo-hookean" || name == "neohookean") {
    *kind = LawKind::NeoHookean;
  } else if (name == "mooney-rivlin" || name == "mooneyrivlin") {
    *kind = LawKind::MooneyRivlin;
  } else {
    return false;
  }
  return true;
}

std::string to_string(LawKind kind) {
  switch (kind) {
    case LawKind::Skalak:
      return "skalak";
    case LawKind::NeoHookean:
      return "neo-hookean";
    case LawKind::MooneyRivlin:
      return "mooney-rivlin";
  }
  return "?";
}

std::shared_ptr<const Law> make_law(const LawOptions& o) {
  std::string err;
  if (!o.IsValid(&err)) throw std::invalid_argument(err);
  switch (o.kind) {
    case LawKind::Skalak:
      return std::make_shared<SkalakLaw>(o.c, o.gs);
    case LawKind::NeoHookean:
      return std::make_shared<NeoHookeanLaw>(o.gs);
    case LawKind::MooneyRivlin:
      return std::make_shared<MooneyRivlinLaw>(o.psi, o.gs);
  }
  throw std::invalid_argument("membrane law: unknown kind");
}

}  // namespace capflow::membrane
