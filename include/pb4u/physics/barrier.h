#pragma once
// IPC's log barrier on a distance (Li et al. 2020, eq. 6): zero from d_hat on, growing without
// bound as d -> 0, and twice continuously differentiable at d_hat:
//   b(d) = -(d - d_hat)^2 ln(d / d_hat)  for 0 < d < d_hat,   0 for d >= d_hat.
// d and d_hat in m; b in m^2 (a stiffness kappa in J/m^2 makes it an energy).
namespace pb4u {

double barrier(double d, double d_hat);
// db/dd (m) and d2b/dd2 (dimensionless); 0 for d >= d_hat. Call with d > 0.
double barrier_derivative(double d, double d_hat);
double barrier_second_derivative(double d, double d_hat);

}  // namespace pb4u
