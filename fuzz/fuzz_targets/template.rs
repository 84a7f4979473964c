//! libFuzzer entry of [`dem_fuzz::template`] (see its doc).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| dem_fuzz::template(data));
