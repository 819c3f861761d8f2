//! Loading glTF 2.0 (`.gltf` and `.glb`) into a [`Scene`](super::Scene).
