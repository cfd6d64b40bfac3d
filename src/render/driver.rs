//! The driver behind the adapter, named for people: which one it is, its
//! version, and whether it is a lavapipe older than the one
//! `tools/setup-debian.sh` installs.
//!
//! Mesa's lavapipe (its CPU Vulkan driver) reports itself to wgpu as the
//! adapter "llvmpipe (LLVM …)", driver "llvmpipe" and driver info
//! "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)" (`VkPhysicalDeviceDriverProperties`;
//! Mesa's `lvp_device.c` writes "Mesa " and its version into `driverInfo`).
//! Mesa 25's lavapipe drew the live viewport 1.3–1.9× faster than Debian
//! 12's 22.3 on 2 cores and offers ray queries (docs/rendering.md,
//! "Drivers"): an older one still renders, and is named with the line that
//! upgrades it.

/// The oldest lavapipe the project installs (`tools/setup-debian.sh`).
pub const LAVAPIPE_MIN_MAJOR: u32 = 25;

/// The one line that upgrades lavapipe on Debian and Ubuntu.
pub const LAVAPIPE_UPGRADE: &str = "sudo tools/setup-debian.sh";

/// Whether the adapter is Mesa's lavapipe (llvmpipe behind Vulkan).
pub fn is_lavapipe(info: &wgpu::AdapterInfo) -> bool {
    info.backend == wgpu::Backend::Vulkan
        && (info.driver == "llvmpipe" || info.name.starts_with("llvmpipe"))
}

/// Mesa's version in a driver info string ("Mesa 25.0.7-2~bpo12+1 (LLVM
/// 15.0.6)" → (25, 0, "25.0.7-2~bpo12+1")); `None` where it does not name
/// Mesa.
pub fn mesa_version(driver_info: &str) -> Option<(u32, u32, &str)> {
    let rest = driver_info.trim().strip_prefix("Mesa ")?;
    let version = rest.split_whitespace().next()?;
    let mut numbers = version.split(['.', '-', '~']);
    let major = numbers.next()?.parse().ok()?;
    let minor = numbers.next()?.parse().ok()?;
    Some((major, minor, version))
}

/// The driver as the status bar's tooltip and `render` name it:
/// "lavapipe, Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)", or the driver's own
/// name and info on other adapters ("NVIDIA, 560.35.03").
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    let name = if is_lavapipe(info) {
        "lavapipe"
    } else if info.driver.is_empty() {
        &info.name
    } else {
        &info.driver
    };
    match info.driver_info.trim() {
        "" => format!("{name} (version not reported)"),
        version => format!("{name}, {version}"),
    }
}

/// Why this driver is not the one the project measures on, with the line
/// that upgrades it: a lavapipe older than Mesa 25. `None` otherwise (a
/// hardware driver, or lavapipe ≥ 25).
pub fn advice(info: &wgpu::AdapterInfo) -> Option<String> {
    if !is_lavapipe(info) {
        return None;
    }
    let note = |what: String| {
        format!(
            "{what}, older than Mesa {LAVAPIPE_MIN_MAJOR}: it renders, but the viewport is slower \
             (1.3–1.9× on 2 cores) and it has no ray queries. Upgrade it: {LAVAPIPE_UPGRADE} \
             (on Debian 12 it takes Mesa 25 from bookworm-backports)"
        )
    };
    match mesa_version(&info.driver_info) {
        Some((major, _, _)) if major >= LAVAPIPE_MIN_MAJOR => None,
        Some((_, _, version)) => Some(note(format!("this is lavapipe from Mesa {version}"))),
        None => Some(note(format!(
            "this lavapipe does not say its Mesa version (\"{}\"); if it is",
            info.driver_info
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(driver: &str, driver_info: &str, backend: wgpu::Backend) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            driver: driver.into(),
            driver_info: driver_info.into(),
            ..wgpu::AdapterInfo::new(wgpu::DeviceType::Cpu, backend)
        }
    }

    // The strings are what Debian 12's two lavapipes report through
    // VK_KHR_driver_properties (wgpu's AdapterInfo::driver_info), read off
    // `render --stats` on this machine with each driver.
    #[test]
    fn mesa_versions_are_read_from_driver_info() {
        assert_eq!(
            mesa_version("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"),
            Some((25, 0, "25.0.7-2~bpo12+1"))
        );
        assert_eq!(
            mesa_version("Mesa 22.3.6 (LLVM 15.0.6)"),
            Some((22, 3, "22.3.6"))
        );
        assert_eq!(mesa_version("NVIDIA 560.35.03"), None);
        assert_eq!(mesa_version(""), None);
    }

    #[test]
    fn an_old_lavapipe_is_named_with_its_upgrade_and_a_new_one_is_not() {
        let old = info(
            "llvmpipe",
            "Mesa 22.3.6 (LLVM 15.0.6)",
            wgpu::Backend::Vulkan,
        );
        let advice_old = advice(&old).expect("Mesa 22 is older than 25");
        assert!(advice_old.contains("Mesa 22.3.6"), "{advice_old}");
        assert!(advice_old.contains(LAVAPIPE_UPGRADE), "{advice_old}");
        let new = info(
            "llvmpipe",
            "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)",
            wgpu::Backend::Vulkan,
        );
        assert_eq!(advice(&new), None);
        assert_eq!(
            describe(&new),
            "lavapipe, Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"
        );
        // llvmpipe behind GL is not lavapipe: no Vulkan advice.
        let gl = info("", "", wgpu::Backend::Gl);
        assert_eq!(advice(&gl), None);
        // A lavapipe that hides its version is named, not passed as new.
        let unknown = info("llvmpipe", "", wgpu::Backend::Vulkan);
        assert!(advice(&unknown).is_some());
    }
}
