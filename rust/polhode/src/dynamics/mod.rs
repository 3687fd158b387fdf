//! Euler's equations, integrators and torques.
