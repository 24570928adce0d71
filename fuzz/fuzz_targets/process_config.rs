#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| kestrel_app::fuzz::process_config(data));
