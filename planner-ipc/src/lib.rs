//! The planner service over iceoryx2 shared memory (work in progress: see the roadmap).
