//! libFuzzer entry of [`dem_fuzz::sweep`] (see its doc).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| dem_fuzz::sweep(data));
