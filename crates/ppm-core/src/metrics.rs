//! Image error metrics (relMSE, RMSE, trimmed relMSE), shared by tests and the CLI. TODO(cli helper)
