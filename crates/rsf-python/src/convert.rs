//! Python values into the library's: keyword arguments into a scene (through its serde
//! form, so the names and the checks are the scene's own) and parameters per fault node
//! (a number, an array or a function of the coordinates called once).

use numpy::{PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;

use crate::errors::invalid;

/// A Python value as JSON: `None`, bools, ints, floats, strings, lists/tuples, dicts.
pub(crate) fn to_json(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Value> {
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if obj.is_instance_of::<PyBool>() {
        return Ok(Value::Bool(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(match obj.extract::<i64>() {
            Ok(i) => Value::from(i),
            Err(_) => Value::from(obj.extract::<f64>()?),
        });
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(Value::from(obj.extract::<f64>()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(Value::String(obj.extract()?));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = obj.extract()?;
        return items.iter().map(|v| to_json(name, v)).collect();
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut map = serde_json::Map::new();
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            map.insert(k.clone(), to_json(&k, &v)?);
        }
        return Ok(Value::Object(map));
    }
    // numpy scalars and anything else that converts to a float.
    match obj.extract::<f64>() {
        Ok(x) => Ok(Value::from(x)),
        Err(_) => Err(invalid(
            name,
            format!(
                "a number, bool, string, list or dict, not {}",
                obj.get_type()
            ),
        )),
    }
}

/// `default` with the fields `fields` replaced, through its serde form: unknown names and
/// wrong types are [`InvalidParameterError`](crate::errors::InvalidParameterError)s naming
/// the keyword (`what`, e.g. "the slider scene", in the message).
pub(crate) fn scene<T: Serialize + DeserializeOwned>(
    default: &T,
    fields: &[(String, Value)],
    what: &str,
) -> PyResult<T> {
    let base = serde_json::to_value(default).map_err(|e| invalid(what, e))?;
    let with = |fields: &[(String, Value)]| -> Result<T, serde_json::Error> {
        let mut v = base.clone();
        if let Value::Object(map) = &mut v {
            for (k, x) in fields {
                map.insert(k.clone(), x.clone());
            }
        }
        serde_json::from_value(v)
    };
    match with(fields) {
        Ok(t) => Ok(t),
        Err(all) => {
            // The first keyword that fails alone is the one named.
            for f in fields {
                if let Err(e) = with(std::slice::from_ref(f)) {
                    return Err(invalid(&f.0, format!("{e} ({what})")));
                }
            }
            Err(invalid(what, all))
        }
    }
}

/// A parameter per fault node: one value everywhere or one per node.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PerNode {
    /// The same value at every node.
    Uniform(f64),
    /// One value per fault node, in fault-node order.
    Values(Vec<f64>),
}

impl PerNode {
    /// The value at fault node `k`.
    pub fn at(&self, k: usize) -> f64 {
        match self {
            PerNode::Uniform(x) => *x,
            PerNode::Values(v) => v[k],
        }
    }

    /// For a checkpoint's fingerprint: the number, or a 64-bit FNV-1a hash of the values'
    /// bits.
    pub fn describe(&self) -> String {
        match self {
            PerNode::Uniform(x) => format!("{x:e}"),
            PerNode::Values(v) => {
                let h = fnv1a(v.iter().flat_map(|x| x.to_bits().to_le_bytes()));
                format!("per node {h:016x}")
            }
        }
    }
}

/// The 64-bit FNV-1a hash of `bytes`: a value's fingerprint that is the same in every
/// process (a function's address is not).
pub(crate) fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Parameter `name` from a number, an array of one value per fault node (shape `(n,)`) or
/// a function of the fault nodes' coordinates `x` (shape `(n, d)`, m) returning such an
/// array or a number — called once, with all nodes.
pub(crate) fn per_node(
    py: Python<'_>,
    name: &str,
    obj: &Bound<'_, PyAny>,
    coords: &[f64],
    d: usize,
) -> PyResult<PerNode> {
    let n = coords.len() / d;
    let value = if obj.is_callable() {
        let x = PyArray2::from_vec2(
            py,
            &coords.chunks(d).map(<[f64]>::to_vec).collect::<Vec<_>>(),
        )
        .map_err(|e| invalid(name, e))?;
        obj.call1((x,))
            .map_err(|e| invalid(name, format!("the function of the coordinates raised {e}")))?
    } else {
        obj.clone()
    };
    if let Ok(x) = value.extract::<f64>() {
        return Ok(PerNode::Uniform(x));
    }
    let np = py.import("numpy")?;
    let array = np
        .call_method1("asarray", (value, "float64"))
        .map_err(|e| invalid(name, format!("a number, an array or a function: {e}")))?;
    let array = array
        .cast_into::<numpy::PyArrayDyn<f64>>()
        .map_err(|e| invalid(name, e))?;
    if array.shape() != [n] {
        return Err(invalid(
            name,
            format!(
                "one value per fault node: shape ({n},), not {:?}",
                array.shape()
            ),
        ));
    }
    Ok(PerNode::Values(
        array.to_vec().map_err(|e| invalid(name, e))?,
    ))
}

/// The value of the keyword `name` that names a choice (`"bem"`, `"closed-form"`): the
/// choice's serde name, as flags and `--config` files spell it.
pub(crate) fn choice<T: DeserializeOwned>(name: &str, value: &str) -> PyResult<T> {
    serde_json::from_value(Value::String(value.to_owned()))
        .map_err(|e| invalid(name, format!("`{value}`: {e}")))
}
