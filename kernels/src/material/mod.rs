//! Constitutive models: flow stress (Johnson–Cook family, Sima–Özel, SCGL, bilinear) and the radial return, always in f64.
