//! Freeing large buffers so that their memory goes back to the system.

/// Frees `v`'s buffer, like dropping it, in a way that keeps glibc's allocator returning
/// large blocks to the system.
///
/// glibc serves a block above its mapping threshold (128 KiB at start) from a mapping of
/// its own, and when such a block is freed it raises the threshold to that block's size
/// (up to 32 MiB). Every later block up to that size then comes from its heaps, whose
/// freed memory mostly stays resident: one freed temporary of 48 bytes per vertex makes
/// the half-edge mesh, the operator and the position buffers of a mesh of a few hundred
/// thousand vertices stay resident after they are freed. Shrinking a mapped block to one
/// element first remaps it smaller, and freeing that small block leaves the threshold
/// where it is. With another allocator this is an ordinary (cheap) drop.
///
/// For the large temporaries of the build and of the smoothing set-up (arrays of a few
/// bytes per vertex or halfedge).
pub fn release<T>(mut v: Vec<T>) {
    if v.capacity() > 1 {
        v.truncate(1);
        v.shrink_to_fit();
    }
    drop(v);
}

#[cfg(test)]
mod tests {
    #[test]
    fn release_frees_any_vector() {
        super::release(vec![0u32; 1 << 20]);
        super::release(Vec::<u64>::new());
        super::release(vec![String::from("a"), String::from("b")]);
        super::release(Vec::<u8>::with_capacity(10));
    }
}
