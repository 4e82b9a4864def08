#[global_allocator]
static ALLOC: physstep::alloc::HugePages = physstep::alloc::HugePages;

fn main() {
    // A million particles' positions in 3D: 24 MB, mapped on their own in 2 MiB pages.
    let x = vec![0.0f64; 3_000_000];
    assert_eq!(x.len(), 3_000_000);
}
