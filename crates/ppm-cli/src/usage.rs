//! Usage errors found after the command line is parsed: a crop window outside the image, a
//! flag the chosen algorithm cannot take, shards that do not fit the iterations. They exit
//! with status 2, as clap's own usage errors do; every other error exits with 1
//! (docs/cli.md, "Exit status").

use std::fmt;

/// A command-line usage error; the message names the flag and says why.
#[derive(Debug)]
pub struct UsageError(pub String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// True if `e` is (or wraps) a [`UsageError`].
pub fn is_usage(e: &anyhow::Error) -> bool {
    e.chain().any(|cause| cause.is::<UsageError>())
}

/// Returns a [`UsageError`] with the formatted message from the enclosing function, as
/// `anyhow::bail!` does for other errors.
macro_rules! usage_bail {
    ($($arg:tt)*) => {
        return Err($crate::usage::UsageError(format!($($arg)*)).into())
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    fn usage() -> anyhow::Result<()> {
        usage_bail!("--spp {} needs -a pt", 3)
    }

    /// A usage error is found under any context added on its way up; other errors are not
    /// usage errors.
    #[test]
    fn usage_errors_are_told_apart_through_context() {
        let e = usage().unwrap_err();
        assert!(is_usage(&e));
        assert_eq!(e.to_string(), "--spp 3 needs -a pt");
        assert!(is_usage(&usage().context("rendering a.yml").unwrap_err()));
        let other = Err::<(), _>(std::io::Error::other("disk full"))
            .context("writing out.exr")
            .unwrap_err();
        assert!(!is_usage(&other));
    }
}
