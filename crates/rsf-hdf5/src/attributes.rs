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
