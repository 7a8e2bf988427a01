// Builds NEROV from the installed headers and integrates one second of motion;
// exits non-zero if anything is off, so CI sees a broken package.
#include <neurov/neurov.hpp>

#include <cstdio>

int main() {
  neurov::Vehicle<double> vehicle;
  if (neurov::Vehicle<double>::create(neurov::nerov_parameters<double>(), vehicle)) return 1;
  neurov::Vector6<double> eta = neurov::Vector6<double>::Zero();
  neurov::Vector6<double> nu = neurov::Vector6<double>::Zero();
  neurov::Vector6<double> tau;
  tau << 100.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  for (int i = 0; i < 50; ++i) {
    if (neurov::rk4_step(vehicle, eta, nu, tau, 0.02) != neurov::Status::ok) return 2;
  }
  std::printf("neurov %s: after 1 s of 100 N surge, x = %.4f m, u = %.4f m/s\n",
              NEUROV_VERSION_STRING, eta(0), nu(0));
  return (eta(0) > 0.0 && nu(0) > 0.0) ? 0 : 3;
}
