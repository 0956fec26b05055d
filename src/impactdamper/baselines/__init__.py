"""Independent methods used to check the exact solver: solve_ivp, fixed-step RK4, an mpmath reference and Siconos."""
