//! libFuzzer entry of [`dem_fuzz::specimen`] (see its doc).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| dem_fuzz::specimen(data));
