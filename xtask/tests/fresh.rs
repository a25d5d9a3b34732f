//! Every file made by a generator of this crate is as the generator writes it: a file
//! edited by hand, or a registry changed without `cargo xtask gen`, fails here.

#[test]
fn generated_files_are_up_to_date() {
    let bad = xtask::out_of_date();
    assert!(bad.is_empty(), "out of date: {bad:?}; run `cargo xtask gen`");
}

/// The C storage of a law is never too small for it, whatever the registry holds (the
/// C API also checks this at compile time).
#[test]
fn storage_words_hold_every_law() {
    for law in xtask::registry::laws() {
        for (i, bytes) in law.slot_bytes.into_iter().enumerate() {
            let words = xtask::ffi_laws::storage_words(bytes);
            assert!(
                words * 8 >= bytes && words.is_multiple_of(8),
                "{} precision {i}: {words} words for {bytes} bytes",
                law.kind
            );
            assert!(law.slot_align[i] <= 8, "{}: alignment {}", law.kind, law.slot_align[i]);
        }
    }
}
