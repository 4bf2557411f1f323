//! The ABI of wire v1 as data: every payload's fields with their C types, offsets and sizes
//! (taken from the Rust types with `offset_of!`), every code, and the C header written from
//! them, `clients/c/planner_wire.h`. The header checks its own layout at compile time
//! (static asserts of every size, alignment and offset); the tests below pin the numbers,
//! keep the checked-in header current and compile it.

use super::{
    Algorithm, Guide, LAYOUT_ROWS, LAYOUT_ROWS_AND_COLUMNS, MAX_COUNT, MAX_RADIUS, MAX_WAYPOINTS,
    MapHeader, PlanParams, PlanRequest, PlanResponseHeader, RequestKind, STATUS_OK, ServiceError,
    TYPE_NAMES, WIRE_VERSION, Waypoint, status::plan_error_code,
};
use core::mem::{align_of, offset_of, size_of};
use planner_core::PlanError;
use std::fmt::Write;

/// One field of a payload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// Field name (the same in Rust, C and Python).
    pub name: &'static str,
    /// C element type (`uint32_t`, `float`, or another payload's C name).
    pub c_type: &'static str,
    /// Array length, `None` for a scalar.
    pub array: Option<usize>,
    /// Byte offset.
    pub offset: usize,
    /// Bytes.
    pub size: usize,
}

/// One payload type.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Payload {
    /// The Rust type's name.
    pub rust_name: &'static str,
    /// The C type's name.
    pub c_name: &'static str,
    /// Bytes.
    pub size: usize,
    /// Alignment in bytes.
    pub align: usize,
    /// Fields in order.
    pub fields: Vec<Field>,
}

macro_rules! field {
    ($t:ty, $name:ident, $c:expr) => {
        field!($t, $name, $c, None)
    };
    ($t:ty, $name:ident, $c:expr, $n:expr) => {
        Field {
            name: stringify!($name),
            c_type: $c,
            array: $n,
            offset: offset_of!($t, $name),
            size: field_size(|value: &$t| &value.$name),
        }
    };
}

/// The size of the field that `project` borrows (no value of `T` needed).
fn field_size<T, F>(_project: fn(&T) -> &F) -> usize {
    size_of::<F>()
}

/// Every payload of wire v1, nested ones first.
pub fn payloads() -> Vec<Payload> {
    vec![
        Payload {
            rust_name: "MapHeader",
            c_name: "planner_v1_map_header",
            size: size_of::<MapHeader>(),
            align: align_of::<MapHeader>(),
            fields: vec![
                field!(MapHeader, wire_version, "uint16_t"),
                field!(MapHeader, layout, "uint8_t"),
                field!(MapHeader, reserved, "uint8_t"),
                field!(MapHeader, map_id, "uint32_t"),
                field!(MapHeader, map_version, "uint32_t"),
                field!(MapHeader, width, "uint32_t"),
                field!(MapHeader, height, "uint32_t"),
                field!(MapHeader, resolution, "float"),
                field!(MapHeader, origin, "float", Some(2)),
            ],
        },
        Payload {
            rust_name: "PlanParams",
            c_name: "planner_v1_plan_params",
            size: size_of::<PlanParams>(),
            align: align_of::<PlanParams>(),
            fields: vec![
                field!(PlanParams, radius, "float"),
                field!(PlanParams, population, "uint32_t"),
                field!(PlanParams, iterations, "uint32_t"),
                field!(PlanParams, stagnation, "uint32_t"),
                field!(PlanParams, clearance, "float"),
                field!(PlanParams, clearance_weight, "float"),
                field!(PlanParams, turn_weight, "float"),
                field!(PlanParams, guide, "uint8_t"),
                field!(PlanParams, reserved, "uint8_t", Some(3)),
            ],
        },
        Payload {
            rust_name: "PlanRequest",
            c_name: "planner_v1_plan_request",
            size: size_of::<PlanRequest>(),
            align: align_of::<PlanRequest>(),
            fields: vec![
                field!(PlanRequest, wire_version, "uint16_t"),
                field!(PlanRequest, kind, "uint8_t"),
                field!(PlanRequest, algorithm, "uint8_t"),
                field!(PlanRequest, reserved, "uint32_t"),
                field!(PlanRequest, request_id, "uint64_t"),
                field!(PlanRequest, seed, "uint64_t"),
                field!(PlanRequest, deadline_us, "uint64_t"),
                field!(PlanRequest, wake_token, "uint64_t"),
                field!(PlanRequest, polls_until_ns, "uint64_t"),
                field!(PlanRequest, map_id, "uint32_t"),
                field!(PlanRequest, map_version, "uint32_t"),
                field!(PlanRequest, start, "int32_t", Some(2)),
                field!(PlanRequest, goal, "int32_t", Some(2)),
                field!(PlanRequest, params, "planner_v1_plan_params"),
            ],
        },
        Payload {
            rust_name: "PlanResponseHeader",
            c_name: "planner_v1_plan_response_header",
            size: size_of::<PlanResponseHeader>(),
            align: align_of::<PlanResponseHeader>(),
            fields: vec![
                field!(PlanResponseHeader, wire_version, "uint16_t"),
                field!(PlanResponseHeader, status, "uint16_t"),
                field!(PlanResponseHeader, algorithm, "uint8_t"),
                field!(PlanResponseHeader, kind, "uint8_t"),
                field!(PlanResponseHeader, reserved, "uint8_t", Some(2)),
                field!(PlanResponseHeader, request_id, "uint64_t"),
                field!(PlanResponseHeader, map_id, "uint32_t"),
                field!(PlanResponseHeader, map_version, "uint32_t"),
                field!(PlanResponseHeader, held_version, "uint32_t"),
                field!(PlanResponseHeader, map_width, "uint32_t"),
                field!(PlanResponseHeader, map_height, "uint32_t"),
                field!(PlanResponseHeader, waypoints, "uint32_t"),
                field!(PlanResponseHeader, length, "float"),
                field!(PlanResponseHeader, turns, "uint32_t"),
                field!(PlanResponseHeader, evaluations, "uint32_t"),
                field!(PlanResponseHeader, time_us, "float"),
                field!(PlanResponseHeader, map_decode_us, "float"),
                field!(PlanResponseHeader, reserved_end, "uint32_t"),
                field!(PlanResponseHeader, max_cells, "uint64_t"),
            ],
        },
        Payload {
            rust_name: "Waypoint",
            c_name: "planner_v1_waypoint",
            size: size_of::<Waypoint>(),
            align: align_of::<Waypoint>(),
            fields: vec![field!(Waypoint, x, "float"), field!(Waypoint, y, "float")],
        },
    ]
}

/// Every named code: `(C macro name, value, meaning)`.
pub fn codes() -> Vec<(String, u64, String)> {
    let mut out = Vec::new();
    let mut push = |name: String, value: u64, what: &str| out.push((name, value, what.to_string()));
    push(
        "WIRE_VERSION".into(),
        WIRE_VERSION.into(),
        "wire_version of every payload header",
    );
    push(
        "MAX_WAYPOINTS".into(),
        MAX_WAYPOINTS as u64,
        "most waypoints in an answer",
    );
    push(
        "MAX_COUNT".into(),
        MAX_COUNT.into(),
        "largest population, iterations, stagnation",
    );
    push(
        "MAX_RADIUS_CELLS".into(),
        MAX_RADIUS as u64,
        "largest robot radius, cells",
    );
    push(
        "LAYOUT_ROWS".into(),
        LAYOUT_ROWS.into(),
        "map words: row-major bits only",
    );
    push(
        "LAYOUT_ROWS_AND_COLUMNS".into(),
        LAYOUT_ROWS_AND_COLUMNS.into(),
        "map words: row-major, then column-major bits",
    );
    for kind in [RequestKind::Plan, RequestKind::MapStatus] {
        let name = match kind {
            RequestKind::Plan => "PLAN",
            RequestKind::MapStatus => "MAP_STATUS",
        };
        push(format!("KIND_{name}"), kind.code().into(), "request kind");
    }
    for a in Algorithm::ALL {
        let name = a.name().to_uppercase().replace('-', "_");
        push(format!("ALGORITHM_{name}"), a.code().into(), a.name());
    }
    for g in Guide::ALL {
        let name = match g {
            Guide::AnyAngle => "ANYANGLE",
            Guide::AStar => "ASTAR",
        };
        push(
            format!("GUIDE_{name}"),
            g.code().into(),
            "corridor guide route",
        );
    }
    push("STATUS_OK".into(), STATUS_OK.into(), "ok");
    for e in PlanError::ALL {
        let name = screaming(e.name());
        push(
            format!("STATUS_{name}"),
            plan_error_code(e).into(),
            e.name(),
        );
    }
    for e in ServiceError::ALL {
        let name = screaming(e.name());
        push(format!("STATUS_{name}"), e.code().into(), e.name());
    }
    out
}

/// `StartOutsideMap` -> `START_OUTSIDE_MAP`.
fn screaming(camel: &str) -> String {
    let mut out = String::new();
    for (i, c) in camel.chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_uppercase());
    }
    out
}

/// The C header of wire v1 (C11 or C++11), as checked in at `clients/c/planner_wire.h`.
pub fn c_header() -> String {
    let mut h = String::new();
    let _ = writeln!(
        h,
        "/* planner_wire.h: the planner service's wire v1 (iceoryx2 payloads).\n\
         * Generated from planner-ipc's wire::abi; do not edit. Regenerate with\n\
         *   PLANNER_BLESS=1 cargo test -p planner-ipc c_header_is_current\n\
         * Protocol reference: docs/wire.md. Little-endian hosts (x86_64, aarch64). */\n\
         #ifndef PLANNER_WIRE_V1_H\n#define PLANNER_WIRE_V1_H\n\n\
         #include <stddef.h>\n#include <stdint.h>\n\n\
         #ifdef __cplusplus\n#define PLANNER_STATIC_ASSERT(c, m) static_assert(c, m)\n\
         #define PLANNER_ALIGNOF(t) alignof(t)\n#else\n\
         #define PLANNER_STATIC_ASSERT(c, m) _Static_assert(c, m)\n\
         #define PLANNER_ALIGNOF(t) _Alignof(t)\n#endif\n"
    );
    for (name, value, what) in codes() {
        let _ = writeln!(h, "#define PLANNER_{name} {value}u /* {what} */");
    }
    let _ = writeln!(
        h,
        "\n/* iceoryx2 type names (the request header is \"()\", map words \"u32\"). */"
    );
    for (short, name) in TYPE_NAMES {
        let _ = writeln!(
            h,
            "#define PLANNER_TYPE_NAME_{} \"{name}\"",
            screaming(short)
        );
    }
    for p in payloads() {
        let upper = p.c_name.to_uppercase();
        let _ = writeln!(
            h,
            "\n/* {} (Rust: planner_ipc::wire::{}) */",
            p.c_name, p.rust_name
        );
        let _ = writeln!(h, "typedef struct {} {{", p.c_name);
        for f in &p.fields {
            let c_type = f.c_type;
            match f.array {
                Some(n) => {
                    let _ = writeln!(h, "    {c_type} {}[{n}];", f.name);
                }
                None => {
                    let _ = writeln!(h, "    {c_type} {};", f.name);
                }
            }
        }
        let _ = writeln!(h, "}} {};", p.c_name);
        let _ = writeln!(h, "#define {upper}_SIZE {}u", p.size);
        let _ = writeln!(h, "#define {upper}_ALIGN {}u", p.align);
        for f in &p.fields {
            let _ = writeln!(
                h,
                "#define {upper}_OFFSET_{} {}u",
                f.name.to_uppercase(),
                f.offset
            );
        }
        let _ = writeln!(
            h,
            "PLANNER_STATIC_ASSERT(sizeof({0}) == {1}_SIZE, \"{0} size\");\n\
             PLANNER_STATIC_ASSERT(PLANNER_ALIGNOF({0}) == {1}_ALIGN, \"{0} alignment\");",
            p.c_name, upper
        );
        for f in &p.fields {
            let _ = writeln!(
                h,
                "PLANNER_STATIC_ASSERT(offsetof({0}, {2}) == {1}_OFFSET_{3}, \"{0}.{2}\");",
                p.c_name,
                upper,
                f.name,
                f.name.to_uppercase()
            );
        }
    }
    let _ = writeln!(h, "\n#endif /* PLANNER_WIRE_V1_H */");
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn header_path() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../clients/c/planner_wire.h")
    }

    /// Sizes, alignments and offsets of wire v1, written out: changing any is a new wire
    /// version.
    #[test]
    fn layouts_are_pinned() {
        type Pinned<'a> = (&'a str, usize, usize, &'a [(&'a str, usize)]);
        let pinned: [Pinned; 5] = [
            (
                "MapHeader",
                32,
                4,
                &[
                    ("wire_version", 0),
                    ("layout", 2),
                    ("reserved", 3),
                    ("map_id", 4),
                    ("map_version", 8),
                    ("width", 12),
                    ("height", 16),
                    ("resolution", 20),
                    ("origin", 24),
                ],
            ),
            (
                "PlanParams",
                32,
                4,
                &[
                    ("radius", 0),
                    ("population", 4),
                    ("iterations", 8),
                    ("stagnation", 12),
                    ("clearance", 16),
                    ("clearance_weight", 20),
                    ("turn_weight", 24),
                    ("guide", 28),
                    ("reserved", 29),
                ],
            ),
            (
                "PlanRequest",
                104,
                8,
                &[
                    ("wire_version", 0),
                    ("kind", 2),
                    ("algorithm", 3),
                    ("reserved", 4),
                    ("request_id", 8),
                    ("seed", 16),
                    ("deadline_us", 24),
                    ("wake_token", 32),
                    ("polls_until_ns", 40),
                    ("map_id", 48),
                    ("map_version", 52),
                    ("start", 56),
                    ("goal", 64),
                    ("params", 72),
                ],
            ),
            (
                "PlanResponseHeader",
                72,
                8,
                &[
                    ("wire_version", 0),
                    ("status", 2),
                    ("algorithm", 4),
                    ("kind", 5),
                    ("reserved", 6),
                    ("request_id", 8),
                    ("map_id", 16),
                    ("map_version", 20),
                    ("held_version", 24),
                    ("map_width", 28),
                    ("map_height", 32),
                    ("waypoints", 36),
                    ("length", 40),
                    ("turns", 44),
                    ("evaluations", 48),
                    ("time_us", 52),
                    ("map_decode_us", 56),
                    ("reserved_end", 60),
                    ("max_cells", 64),
                ],
            ),
            ("Waypoint", 8, 4, &[("x", 0), ("y", 4)]),
        ];
        let payloads = payloads();
        assert_eq!(payloads.len(), pinned.len());
        for (p, (name, size, align, fields)) in payloads.iter().zip(pinned) {
            assert_eq!((p.rust_name, p.size, p.align), (name, size, align));
            let got: Vec<(&str, usize)> = p.fields.iter().map(|f| (f.name, f.offset)).collect();
            assert_eq!(got, fields, "{name}");
            // No implicit padding: the fields tile the payload.
            let mut end = 0;
            for f in &p.fields {
                assert_eq!(f.offset, end, "{name}.{} leaves a gap", f.name);
                end = f.offset + f.size;
            }
            assert_eq!(end, p.size, "{name} ends in padding");
        }
    }

    /// `clients/c/planner_wire.h` is what this build writes (`PLANNER_BLESS=1` rewrites it).
    #[test]
    fn c_header_is_current() {
        let path = header_path();
        let want = c_header();
        if std::env::var_os("PLANNER_BLESS").is_some() {
            std::fs::write(&path, &want).unwrap();
        }
        let have =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            have == want,
            "{} is stale: run PLANNER_BLESS=1 cargo test -p planner-ipc c_header_is_current",
            path.display()
        );
    }

    /// The header compiles as C11 and as C++11 with its static asserts of every size,
    /// alignment and offset, so a C compiler lays the structures out as Rust does.
    #[test]
    fn c_header_compiles_with_the_rust_layout() {
        let dir = std::env::temp_dir().join(format!("planner-wire-h-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let header = header_path();
        let source = dir.join("check.c");
        std::fs::write(
            &source,
            format!(
                "#include \"{}\"\n#include <string.h>\nint main(void) {{ \
                 planner_v1_plan_request r; memset(&r, 0, sizeof r); \
                 r.wire_version = PLANNER_WIRE_VERSION; return r.kind; }}\n",
                header.display()
            ),
        )
        .unwrap();
        for (compiler, std_flag, lang) in [("cc", "-std=c11", "c"), ("c++", "-std=c++11", "c++")] {
            let out = std::process::Command::new(compiler)
                .args([
                    std_flag,
                    "-Wall",
                    "-Wextra",
                    "-Werror",
                    "-pedantic",
                    "-x",
                    lang,
                ])
                .arg(&source)
                .arg("-o")
                .arg(dir.join(format!("check-{lang}")))
                .output()
                .unwrap_or_else(|e| panic!("{compiler} (needed to check the C header): {e}"));
            assert!(
                out.status.success(),
                "{compiler}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
