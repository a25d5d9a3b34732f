//! `wmr_py.read_log`: a ROS 2 MCAP's `/cmd_vel`, `/joint_states` and `/odom` as the table
//! `wmr-cli log2csv` writes (`wmr_ros2::log`), columns of float64 arrays.

use numpy::IntoPyArray as _;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::parameter_error;

/// Reads the ROS 2 MCAP at `path` (a wmr `--profile ros2` file, or a robot's
/// `ros2 bag record -s mcap`): a dict of float64 arrays, `t` (s, the messages' stamps) and
/// wmr's columns `x, y, theta, v, omega` (`/odom`), `phi_r, phi_l, omega_r, omega_l,
/// tau_r, tau_l` (`/joint_states`), `v_cmd, omega_cmd` (`/cmd_vel`): a row at every
/// message time, each column the latest value (NaN before its topic's first message).
/// `namespace` picks one run's topics (`/run1`). Bad files raise ParameterError (key
/// `path`); unreadable ones OSError.
#[pyfunction]
#[pyo3(signature = (path, namespace = None))]
pub fn read_log<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    namespace: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let log = py.detach(|| wmr_ros2::log::read_log_file(&path, namespace)).map_err(|e| match e {
        wmr_ros2::log::LogFileError::Io(io) => PyErr::from(io),
        bad => parameter_error("path", format!("{}: {bad}", path.display())),
    })?;
    let table = log.table();
    let out = PyDict::new(py);
    out.set_item("t", table.t.into_pyarray(py))?;
    for (name, column) in wmr_ros2::log::LOG_COLUMNS.into_iter().zip(table.columns) {
        out.set_item(name, column.into_pyarray(py))?;
    }
    Ok(out)
}
