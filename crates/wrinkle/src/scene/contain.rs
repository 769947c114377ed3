//! A last guard around third-party parsers that panic on malformed input instead of returning an error
//! (the gltf crate unwraps and slices unchecked in places its validation does not reach): the panic is
//! caught, kept silent, and becomes the caller's one-line error. wrinkle's own checks come first; this only
//! keeps the promise of one line and no crash for what they miss.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    /// Set while this thread runs a contained parser: its panics are not printed.
    static CONTAINED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `parse`; a panic in it comes back as `Err` with its message, and prints nothing.
pub fn contain_panics<T>(parse: impl FnOnce() -> T) -> Result<T, String> {
    static QUIET_HOOK: Once = Once::new();
    QUIET_HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !CONTAINED.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = CONTAINED.with(|c| c.replace(true));
    let result = panic::catch_unwind(AssertUnwindSafe(parse));
    CONTAINED.with(|c| c.set(was));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "an unexplained failure".into())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_its_message_and_other_results_pass_through() {
        assert_eq!(contain_panics(|| 7), Ok(7));
        let slice: &[u8] = &[1, 2, 3];
        let at = std::hint::black_box(5);
        let err = contain_panics(|| slice[at]).unwrap_err();
        assert!(err.contains("index out of bounds"), "{err}");
        assert_eq!(contain_panics(|| panic!("{}", "formatted")), Err::<(), _>("formatted".to_string()));
    }
}
