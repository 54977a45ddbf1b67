//! Text attributes (units, descriptions, a file's header) on HDF5 objects.

use hdf5::types::VarLenUnicode;
use hdf5::Location;

/// Sets the attribute `name` of `at` to the text `value` (a variable-length UTF-8 string,
/// what h5py reads as `str`), replacing one of that name.
pub(crate) fn text(at: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    if at.attr_names()?.iter().any(|n| n == name) {
        at.delete_attr(name)?;
    }
    let value: VarLenUnicode = value
        .parse()
        .map_err(|e| hdf5::Error::from(format!("attribute `{name}`: {e}")))?;
    at.new_attr::<VarLenUnicode>()
        .shape(())
        .create(name)?
        .write_scalar(&value)
}

/// The text attribute `name` of `at`, if it has one.
pub(crate) fn read_text(at: &Location, name: &str) -> hdf5::Result<Option<String>> {
    if !at.attr_names()?.iter().any(|n| n == name) {
        return Ok(None);
    }
    let value: VarLenUnicode = at.attr(name)?.read_scalar()?;
    Ok(Some(value.as_str().to_owned()))
}
