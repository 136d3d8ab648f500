//! Photons: the compact record, the lock-free append buffer and the hash grid. TODO(photon helper)
