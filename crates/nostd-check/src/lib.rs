//! Compile-time proof that `kestrel-core`, `kestrel-models`,
//! `kestrel-adaptive` and the `kestrel` umbrella without its default
//! features are `no_std`.
//!
//! `cargo check -p kestrel-nostd-check --features check` builds this crate with
//! its own panic handler. If any dependency pulled in `std`, the build would
//! fail with a duplicate `panic_impl` lang item.
#![no_std]

pub use kestrel;
pub use kestrel_adaptive;
pub use kestrel_core;
pub use kestrel_models;

#[cfg(feature = "check")]
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    loop {}
}
