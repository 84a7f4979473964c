//! libFuzzer entry of [`dem_fuzz::grains`] (see its doc).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| dem_fuzz::grains(data));
