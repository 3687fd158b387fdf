//! The exact torque-free motion: Jacobi elliptic functions and the free rotation.
