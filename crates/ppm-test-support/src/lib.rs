//! Test support shared by the workspace's test suites (not published): small scenes built in
//! code with per-pixel statistics ([`test_scenes`]), a render's relative MSE against a
//! reference image and its noise-only value ([`rel_mse`]), and the generator of the shipped Cornell
//! boxes' meshes ([`meshes`]). A crate of its own, so that suites of other crates use it as a
//! dependency instead of reaching into another crate's `tests/` folder by path.

pub mod meshes;
pub mod rel_mse;
pub mod test_scenes;
