// capflow/membrane/law: isotropic hyperelastic membrane laws (paper eqs. 11-13).
//
// Every law is written through its strain energy per REFERENCE area w(I1, I2), with the
// invariants of the left Cauchy-Green tensor B = A A^T (principal stretches l1, l2):
//   I1 = l1^2 + l2^2 - 2 = tr B - 2,     I2 = (l1 l2)^2 - 1 = Js^2 - 1.
// The in-plane tension tensor (force per CURRENT length) then follows for every law as
//   tau = (2/Js) w_1 B + 2 Js w_2 P,     w_a = dw/dI_a,  P = I - n n,                  (*)
// i.e. tau = cB B + cP P, and the principal tensions are tau_a = cP + cB l_a^2, equal to
// tau_1 = (1/l2) dw/dl1. (*) is the Cartesian form: it needs no eigen-decomposition and is
// smooth where l1 = l2.
//
// Laws (all in units of Gs; Law::energy/tension_coefficients multiply by gs()):
//   Skalak (parameter C, area modulus (1+2C) Gs, needs C > -1/2):
//     w = (1/4)(I1^2 + 2 I1 - 2 I2 + C I2^2)
//     tau_1 = (l1/l2)(l1^2 - 1 + C l2^2((l1 l2)^2 - 1))               (paper eq. 11)
//     Cartesian: tau = (1/Js)(B.B - B) + C Js (Js^2 - 1) P
//   neo-Hookean (area modulus 3 Gs):
//     w = (1/2)(I1 - 1 + 1/(I2 + 1))
//     tau_1 = (1/(l1 l2))(l1^2 - 1/(l1 l2)^2)                          (paper eq. 13)
//     Cartesian: tau = (1/Js)(B - Js^-2 P)
//   Mooney-Rivlin (parameter Psi in [0,1]; Psi = 1 is neo-Hookean; area modulus 3 Gs):
//     w = (Psi/2)(I1 - 1 + 1/(I2+1)) + ((1-Psi)/2)((I1 + 2)/(I2 + 1) + I2 - 2)
//     (the thin incompressible 3-D Mooney-Rivlin solid with C1 = Psi/2, C2 = (1-Psi)/2:
//      the second term is (1/2)(l1^-2 + l2^-2 + (l1 l2)^2 - 3))
//     tau_1 = (1/(l1 l2))(l1^2 - 1/(l1 l2)^2)(Psi + l2^2 (1 - Psi))    (paper eq. 12)
//     Cartesian (derived from (*), using B^-1 = ((tr B) P - B)/Js^2 in the plane):
//       tau = Psi (1/Js)(B - Js^-2 P) + (1-Psi)(B/Js^3 + (Js - tr B/Js^3) P)
// All three have small-strain shear modulus Gs.
//
// Adding a law: derive from Law, implement name(), unit_energy() (w and its two partial
// derivatives, units of Gs) and unit_principal_tension() (the law's own principal formula,
// used for output checks and tests); register it in LawKind/make_law.
//
// Failure modes: make_law throws std::invalid_argument for invalid options (see IsValid).
// The laws themselves assume Js > 0 (callers check).
#pragma once

#include <memory>
#include <string>

namespace capflow::membrane {

// w(I1, I2) and its partial derivatives w_1 = dw/dI1, w_2 = dw/dI2.
struct EnergyDerivatives {
  double w = 0, w1 = 0, w2 = 0;
};

class Law {
 public:
  explicit Law(double gs) : gs_(gs) {}
  virtual ~Law() = default;

  virtual std::string name() const = 0;
  // Energy per reference area and derivatives, in units of Gs.
  virtual EnergyDerivatives unit_energy(double i1, double i2) const = 0;
  // The law's principal tension tau_1(l1, l2) in units of Gs (tau_2 = tau_1(l2, l1)).
  virtual double unit_principal_tension(double l1, double l2) const = 0;

  double gs() const { return gs_; }
  EnergyDerivatives energy(double i1, double i2) const {
    EnergyDerivatives d = unit_energy(i1, i2);
    d.w *= gs_;
    d.w1 *= gs_;
    d.w2 *= gs_;
    return d;
  }
  double principal_tension(double l1, double l2) const {
    return gs_ * unit_principal_tension(l1, l2);
  }
  // tau = cb B + cp P, from (*): cb = 2 w_1/Js, cp = 2 Js w_2 (scaled by Gs).
  void tension_coefficients(double i1, double js, double* cb, double* cp) const {
    const EnergyDerivatives d = energy(i1, js * js - 1.0);
    *cb = 2.0 * d.w1 / js;
    *cp = 2.0 * js * d.w2;
  }

 private:
  double gs_;
};

class SkalakLaw final : public Law {
 public:
  explicit SkalakLaw(double c, double gs = 1.0) : Law(gs), c_(c) {}
  std::string name() const override { return "skalak"; }
  EnergyDerivatives unit_energy(double i1, double i2) const override;
  double unit_principal_tension(double l1, double l2) const override;
  double c() const { return c_; }

 private:
  double c_;
};

class NeoHookeanLaw final : public Law {
 public:
  explicit NeoHookeanLaw(double gs = 1.0) : Law(gs) {}
  std::string name() const override { return "neo-hookean"; }
  EnergyDerivatives unit_energy(double i1, double i2) const override;
  double unit_principal_tension(double l1, double l2) const override;
};

class MooneyRivlinLaw final : public Law {
 public:
  explicit MooneyRivlinLaw(double psi, double gs = 1.0) : Law(gs), psi_(psi) {}
  std::string name() const override { return "mooney-rivlin"; }
  EnergyDerivatives unit_energy(double i1, double i2) const override;
  double unit_principal_tension(double l1, double l2) const override;
  double psi() const { return psi_; }

 private:
  double psi_;
};

enum class LawKind { Skalak, NeoHookean, MooneyRivlin };

// Typed law options (the control file fills these; no parsing here).
struct LawOptions {
  LawKind kind = LawKind::Skalak;  // which law
  double c = 1.0;                  // Skalak area-dilatation parameter C (> -1/2), dimensionless
  double psi = 1.0;                // Mooney-Rivlin Psi in [0, 1]
  double gs = 1.0;                 // shear modulus Gs (> 0); 1 in the dimensionless scaling
  // False with a message naming the field if an option is out of range.
  bool IsValid(std::string* error) const;
};

// "skalak", "neo-hookean" (or "neohookean"), "mooney-rivlin" (or "mooneyrivlin").
bool parse_law_kind(const std::string& name, LawKind* kind);
std::string to_string(LawKind kind);

// Throws std::invalid_argument with IsValid's message for invalid options.
std::shared_ptr<const Law> make_law(const LawOptions& options);

}  // namespace capflow::membrane
