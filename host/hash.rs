//! FNV-1a, 64 bits: the checksum of checkpoint buffers and the hash of scenes and materials. A fixed algorithm
//! with fixed constants, so that the same bytes give the same value on every run and machine (std's hashers are
//! randomly seeded or unspecified). It detects damage and edits, not a deliberate forgery.

const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const PRIME: u64 = 0x0000_0100_0000_01b3;

/// The FNV-1a 64 hash of `bytes`.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(OFFSET, |h, &b| (h ^ u64::from(b)).wrapping_mul(PRIME))
}
