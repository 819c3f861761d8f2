//! What kinds of scattering a BSDF has: reflection and/or transmission, each diffuse, glossy
//! or specular (a delta lobe). Integrators ask these instead of the BSDF's type: light
//! sampling is skipped where every lobe is specular, light from below the surface is
//! considered only where the BSDF transmits, and the direct integrator follows specular lobes
//! only. After pbrt-v4's `BxDFFlags` and Mitsuba 3's `BSDFFlags`.

bitflags::bitflags! {
    /// The lobes a BSDF has (see the module doc).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
    pub struct BsdfFlags: u8 {
        /// Scatters back to the side light arrived from.
        const REFLECTION = 1;
        /// Scatters through the surface.
        const TRANSMISSION = 1 << 1;
        /// A lobe with a smooth, wide density (Lambert).
        const DIFFUSE = 1 << 2;
        /// A lobe with a peaked but finite density (rough microfacets, sheen).
        const GLOSSY = 1 << 3;
        /// A delta lobe (mirror, smooth glass): no density, no light sampling can reach it.
        const SPECULAR = 1 << 4;
    }
}

impl BsdfFlags {
    /// Whether the BSDF scatters at all.
    #[inline]
    pub fn scatters(self) -> bool {
        self.intersects(Self::REFLECTION | Self::TRANSMISSION)
    }

    /// Whether some lobe has a density (diffuse or glossy): light sampling can reach it.
    #[inline]
    pub fn has_density(self) -> bool {
        self.intersects(Self::DIFFUSE | Self::GLOSSY)
    }

    /// Whether every lobe is a delta lobe (light sampling is pointless).
    #[inline]
    pub fn is_specular_only(self) -> bool {
        !self.has_density()
    }

    /// Whether the BSDF may transmit.
    #[inline]
    pub fn transmits(self) -> bool {
        self.contains(Self::TRANSMISSION)
    }

    /// The lobe kind of a microfacet lobe: specular when its distribution is smooth.
    #[inline]
    pub fn microfacet(smooth: bool) -> Self {
        if smooth { Self::SPECULAR } else { Self::GLOSSY }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flag_questions_follow_the_lobes() {
        let diffuse = BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE;
        assert!(diffuse.has_density() && !diffuse.transmits() && diffuse.scatters());
        let glass = BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR;
        assert!(glass.is_specular_only() && glass.transmits());
        assert!(!BsdfFlags::empty().scatters());
        assert_eq!(BsdfFlags::microfacet(true), BsdfFlags::SPECULAR);
        assert_eq!(BsdfFlags::microfacet(false), BsdfFlags::GLOSSY);
    }
}
