//! `dbot.Bench`: the servo bench of `dbot dxl` (`board::bench`) from Python — scan IDs, read and
//! write registers by e-manual field name or address, set up ID, baud and Return Delay Time.
//! Bad input (a field name, a value, a rate) is `ValueError`; a servo or port that fails is
//! `dbot.BoardError`; both carry the library's words, the ones `dbot dxl` prints.

use ::board::bench::{BaudChoice, Bench as HostBench, BenchError, Reading, SetupRequest, Target};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{board_error, value_error};

/// The error and its causes, as `dbot` prints them: `what: why: why`.
fn chain(e: &BenchError) -> String {
    let mut text = e.to_string();
    let mut src = std::error::Error::source(e);
    while let Some(s) = src {
        text.push_str(": ");
        text.push_str(&s.to_string());
        src = s.source();
    }
    text
}

fn py_err(e: BenchError) -> PyErr {
    match e {
        BenchError::UnknownField { .. }
        | BenchError::BadLength { .. }
        | BenchError::WriteSize { .. }
        | BenchError::ValueRange { .. }
        | BenchError::ReturnDelay { .. }
        | BenchError::NewIdRange { .. }
        | BenchError::NewBaud { .. }
        | BenchError::NotSerialPort { .. } => value_error(chain(&e)),
        _ => board_error(chain(&e)),
    }
}

fn target<'a>(
    field: Option<&'a str>,
    addr: Option<u16>,
    length: Option<u16>,
) -> PyResult<Target<'a>> {
    match (field, addr, length) {
        (Some(name), None, None) => Ok(Target::Field(name)),
        (None, Some(addr), Some(len)) => Ok(Target::Addr { addr, len }),
        _ => Err(value_error("give field=NAME, or addr=ADDR and length=LEN")),
    }
}

fn reading<'py>(py: Python<'py>, r: &Reading) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("id", r.id)?;
    d.set_item("field", r.field.name)?;
    d.set_item("addr", r.field.addr)?;
    d.set_item("length", r.field.size)?;
    d.set_item("value", r.unsigned())?;
    d.set_item("signed", r.signed())?;
    d.set_item("bytes", r.bytes.clone())?;
    d.set_item("alert", r.alert)?;
    Ok(d)
}

/// Dynamixel servos on a USB serial adapter (U2D2) or `dbot sim-bus`, as `dbot dxl` reaches them.
#[pyclass(module = "dbot._native", unsendable)]
#[derive(Debug)]
pub struct Bench {
    inner: HostBench,
}

#[pymethods]
impl Bench {
    /// Opens nothing yet: the port is opened on first use, at `baud` (bit/s, an MX(2.0) rate) or,
    /// with `"auto"`, at the first MX rate where servos answer.
    #[staticmethod]
    #[pyo3(signature = (port, baud = None, reply_slack_us = 20_000))]
    fn open(port: &str, baud: Option<&Bound<'_, PyAny>>, reply_slack_us: u32) -> PyResult<Self> {
        let choice = match baud {
            None => BaudChoice::Rate(::board::bench::FACTORY_BAUD),
            Some(b) => b
                .str()?
                .to_str()?
                .parse::<BaudChoice>()
                .map_err(value_error)?,
        };
        Ok(Self {
            inner: HostBench::new(port, choice, reply_slack_us),
        })
    }

    /// The rate in use, once the port is open.
    #[getter]
    fn baud(&self) -> Option<u32> {
        self.inner.baud()
    }

    /// Closes the port (it is opened exclusively), so `dbot dxl` or another `Bench` can use it;
    /// a later call opens it again.
    fn close(&mut self) {
        self.inner.close();
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&mut self, _args: &Bound<'_, pyo3::types::PyTuple>) -> bool {
        self.close();
        false
    }

    /// Pings IDs 0..=max_id; one dict per servo that answers
    /// (`id`, `model_number`, `model`, `firmware`, `alert`, `baud`).
    #[pyo3(signature = (max_id = 252))]
    fn scan<'py>(&mut self, py: Python<'py>, max_id: u8) -> PyResult<Vec<Bound<'py, PyDict>>> {
        if max_id > 252 {
            return Err(value_error(format!("max_id {max_id}: IDs go up to 252")));
        }
        let scan = self.inner.scan(max_id, |_| {}).map_err(py_err)?;
        scan.found
            .iter()
            .map(|f| {
                let d = PyDict::new(py);
                d.set_item("id", f.id)?;
                d.set_item("model_number", f.model_number)?;
                d.set_item("model", f.model.map(|m| m.name()))?;
                d.set_item("firmware", f.firmware)?;
                d.set_item("alert", f.alert)?;
                d.set_item("baud", scan.baud)?;
                Ok(d)
            })
            .collect()
    }

    /// Reads a register of servo `id` by e-manual field name, or `addr` and `length` bytes.
    #[pyo3(signature = (id, field = None, addr = None, length = None))]
    fn read<'py>(
        &mut self,
        py: Python<'py>,
        id: u8,
        field: Option<&str>,
        addr: Option<u16>,
        length: Option<u16>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let t = target(field, addr, length)?;
        let r = self.inner.read(id, t).map_err(py_err)?;
        reading(py, &r)
    }

    /// Writes `value` (1, 2 or 4 bytes, little endian, signed as two's complement) to a field by
    /// name or to `addr` (`length` bytes).
    #[pyo3(signature = (id, value, field = None, addr = None, length = None))]
    fn write(
        &mut self,
        id: u8,
        value: i64,
        field: Option<&str>,
        addr: Option<u16>,
        length: Option<u16>,
    ) -> PyResult<()> {
        let t = target(field, addr, length)?;
        self.inner.write(id, t, value).map_err(py_err)?;
        Ok(())
    }

    /// Torque off, then Return Delay Time, ID and baud (in that order); returns the servo's answer
    /// at its new ID and rate (`id`, `baud`, `model_number`, `firmware`).
    #[pyo3(signature = (id, new_id = None, new_baud = None, return_delay_us = None))]
    fn setup<'py>(
        &mut self,
        py: Python<'py>,
        id: u8,
        new_id: Option<u8>,
        new_baud: Option<u32>,
        return_delay_us: Option<u32>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let req = SetupRequest {
            new_id,
            new_baud,
            return_delay_us,
        };
        let done = self.inner.setup(id, req).map_err(py_err)?;
        let d = PyDict::new(py);
        d.set_item("id", done.id)?;
        d.set_item("baud", done.baud)?;
        d.set_item("model_number", done.model_number)?;
        d.set_item("firmware", done.firmware)?;
        Ok(d)
    }
}
