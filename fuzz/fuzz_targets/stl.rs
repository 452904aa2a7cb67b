//! An STL file, ASCII or binary (a model for `info`, an asset for `i()`): read, then measured as `shapegram info` measures it and written in every format.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let read = shapegram_export::read_stl(bytes);
    match read {
        Ok(model) => shapegram_fuzz::finish(&model),
        Err(error) => drop(error.to_string()),
    }
});
