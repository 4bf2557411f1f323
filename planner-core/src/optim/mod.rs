//! Swarm optimizers over a box `[lb, ub]^D` with fixed capacity (SPEC section 2).
