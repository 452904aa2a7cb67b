//! A handle on two threads: a second call while a derivation runs is refused with `SG_BUSY`,
//! `sg_state_progress` counts and `sg_state_cancel` stops the derivation.

use std::ffi::CString;
use std::time::{Duration, Instant};

use shapegram_ffi::*;

/// A handle that may cross to another thread for the test (the ABI allows it).
struct Handle(*mut sg_state);
// SAFETY: the ABI documents handles as movable between threads and refuses concurrent calls.
unsafe impl Send for Handle {}
unsafe impl Sync for Handle {}

#[test]
fn a_running_derivation_refuses_other_calls_reports_progress_and_can_be_cancelled() {
    // 2^24 leaves: minutes unoptimised, so it is surely running when cancelled.
    let text = CString::new(
        "Lot --> A(0)\nA(d) --> case d < 24 : split(x) { ~1 : A(d + 1) | ~1 : A(d + 1) } else : X\n",
    )
    .unwrap();
    let state = Handle(sg_state_new());
    assert_eq!(
        sg_state_load_text(state.0, text.as_ptr(), SG_KIND_CGA, std::ptr::null()),
        sg_status::SG_OK
    );
    let started = Instant::now();
    std::thread::scope(|scope| {
        let handle = &state;
        let worker = scope.spawn(move || sg_state_derive(handle.0));
        let mut applications = 0;
        while applications == 0 {
            assert!(started.elapsed() < Duration::from_secs(60), "no progress");
            std::thread::sleep(Duration::from_millis(5));
            assert_eq!(
                sg_state_progress(state.0, &mut applications),
                sg_status::SG_OK
            );
        }
        assert_eq!(sg_state_set_seed(state.0, 1), sg_status::SG_BUSY);
        assert_eq!(sg_state_free(state.0), sg_status::SG_BUSY);
        let busy = unsafe { std::ffi::CStr::from_ptr(sg_state_last_error(state.0)) };
        assert_eq!(
            busy.to_str().unwrap(),
            "the handle is busy: another call on it is running"
        );
        assert_eq!(sg_state_cancel(state.0), sg_status::SG_OK);
        assert_eq!(worker.join().unwrap(), sg_status::SG_CANCELLED);
    });
    assert!(started.elapsed() < Duration::from_secs(60));
    let message = unsafe { std::ffi::CStr::from_ptr(sg_state_last_error(state.0)) };
    assert_eq!(message.to_str().unwrap(), "the derivation was cancelled");
    // The handle works again, and a new derivation is not cancelled by the old request.
    let small = CString::new("Lot --> extrude(3) X\n").unwrap();
    assert_eq!(
        sg_state_load_text(state.0, small.as_ptr(), SG_KIND_CGA, std::ptr::null()),
        sg_status::SG_OK
    );
    assert_eq!(sg_state_derive(state.0), sg_status::SG_OK);
    let mut mesh = std::mem::MaybeUninit::<sg_mesh>::uninit();
    assert_eq!(sg_state_mesh(state.0, mesh.as_mut_ptr()), sg_status::SG_OK);
    let mesh = unsafe { mesh.assume_init() };
    // A box: six faces of four corners, two triangles each.
    assert_eq!(
        (mesh.vertex_count, mesh.index_count, mesh.part_count),
        (24, 36, 1)
    );
    assert_eq!(sg_state_free(state.0), sg_status::SG_OK);
}
