/* planner_wire.h: the planner service's wire v1 (iceoryx2 payloads).
* Generated from planner-ipc's wire::abi; do not edit. Regenerate with
*   PLANNER_BLESS=1 cargo test -p planner-ipc c_header_is_current
* Protocol reference: docs/wire.md. Little-endian hosts (x86_64, aarch64). */
#ifndef PLANNER_WIRE_V1_H
#define PLANNER_WIRE_V1_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
#define PLANNER_STATIC_ASSERT(c, m) static_assert(c, m)
#define PLANNER_ALIGNOF(t) alignof(t)
#else
#define PLANNER_STATIC_ASSERT(c, m) _Static_assert(c, m)
#define PLANNER_ALIGNOF(t) _Alignof(t)
#endif

#define PLANNER_WIRE_VERSION 1u /* wire_version of every payload header */
#define PLANNER_MAX_WAYPOINTS 16384u /* most waypoints in an answer */
#define PLANNER_MAX_COUNT 16777216u /* largest population, iterations, stagnation */
#define PLANNER_MAX_RADIUS_CELLS 1024u /* largest robot radius, cells */
#define PLANNER_LAYOUT_ROWS 0u /* map words: row-major bits only */
#define PLANNER_LAYOUT_ROWS_AND_COLUMNS 1u /* map words: row-major, then column-major bits */
#define PLANNER_KIND_PLAN 0u /* request kind */
#define PLANNER_KIND_MAP_STATUS 1u /* request kind */
#define PLANNER_ALGORITHM_ASTAR 1u /* astar */
#define PLANNER_ALGORITHM_THETA 2u /* theta */
#define PLANNER_ALGORITHM_ACO 3u /* aco */
#define PLANNER_ALGORITHM_TCLHHO 4u /* tclhho */
#define PLANNER_ALGORITHM_IGWO 5u /* igwo */
#define PLANNER_ALGORITHM_HHO 6u /* hho */
#define PLANNER_ALGORITHM_GWO 7u /* gwo */
#define PLANNER_ALGORITHM_TGWO 8u /* tgwo */
#define PLANNER_ALGORITHM_PSO 9u /* pso */
#define PLANNER_ALGORITHM_GA 10u /* ga */
#define PLANNER_ALGORITHM_SSA 11u /* ssa */
#define PLANNER_ALGORITHM_SSAGWO 12u /* ssagwo */
#define PLANNER_ALGORITHM_ANYANGLE 13u /* anyangle */
#define PLANNER_GUIDE_ANYANGLE 0u /* corridor guide route */
#define PLANNER_GUIDE_ASTAR 1u /* corridor guide route */
#define PLANNER_STATUS_OK 0u /* ok */
#define PLANNER_STATUS_START_OUTSIDE_MAP 1u /* StartOutsideMap */
#define PLANNER_STATUS_GOAL_OUTSIDE_MAP 2u /* GoalOutsideMap */
#define PLANNER_STATUS_START_OCCUPIED 3u /* StartOccupied */
#define PLANNER_STATUS_GOAL_OCCUPIED 4u /* GoalOccupied */
#define PLANNER_STATUS_NO_VALID_PATH 5u /* NoValidPath */
#define PLANNER_STATUS_CAPACITY_EXCEEDED 6u /* CapacityExceeded */
#define PLANNER_STATUS_INVALID_PARAMETERS 7u /* InvalidParameters */
#define PLANNER_STATUS_BUDGET_EXHAUSTED 8u /* BudgetExhausted */
#define PLANNER_STATUS_UNKNOWN_MAP 101u /* UnknownMap */
#define PLANNER_STATUS_STALE_MAP_VERSION 102u /* StaleMapVersion */
#define PLANNER_STATUS_MAP_TOO_LARGE 103u /* MapTooLarge */
#define PLANNER_STATUS_UNKNOWN_ALGORITHM 104u /* UnknownAlgorithm */
#define PLANNER_STATUS_INVALID_REQUEST 105u /* InvalidRequest */
#define PLANNER_STATUS_CANCELLED 106u /* Cancelled */
#define PLANNER_STATUS_SERVER_SHUTTING_DOWN 107u /* ServerShuttingDown */
#define PLANNER_STATUS_DEADLINE_EXCEEDED 108u /* DeadlineExceeded */
#define PLANNER_STATUS_INTERNAL 109u /* Internal */
#define PLANNER_STATUS_UNSUPPORTED_VERSION 110u /* UnsupportedVersion */

/* iceoryx2 type names (the request header is "()", map words "u32"). */
#define PLANNER_TYPE_NAME_MAP_HEADER "planner.v1.MapHeader"
#define PLANNER_TYPE_NAME_PLAN_REQUEST "planner.v1.PlanRequest"
#define PLANNER_TYPE_NAME_PLAN_RESPONSE_HEADER "planner.v1.PlanResponseHeader"
#define PLANNER_TYPE_NAME_WAYPOINT "planner.v1.Waypoint"

/* planner_v1_map_header (Rust: planner_ipc::wire::MapHeader) */
typedef struct planner_v1_map_header {
    uint16_t wire_version;
    uint8_t layout;
    uint8_t reserved;
    uint32_t map_id;
    uint32_t map_version;
    uint32_t width;
    uint32_t height;
    float resolution;
    float origin[2];
} planner_v1_map_header;
#define PLANNER_V1_MAP_HEADER_SIZE 32u
#define PLANNER_V1_MAP_HEADER_ALIGN 4u
#define PLANNER_V1_MAP_HEADER_OFFSET_WIRE_VERSION 0u
#define PLANNER_V1_MAP_HEADER_OFFSET_LAYOUT 2u
#define PLANNER_V1_MAP_HEADER_OFFSET_RESERVED 3u
#define PLANNER_V1_MAP_HEADER_OFFSET_MAP_ID 4u
#define PLANNER_V1_MAP_HEADER_OFFSET_MAP_VERSION 8u
#define PLANNER_V1_MAP_HEADER_OFFSET_WIDTH 12u
#define PLANNER_V1_MAP_HEADER_OFFSET_HEIGHT 16u
#define PLANNER_V1_MAP_HEADER_OFFSET_RESOLUTION 20u
#define PLANNER_V1_MAP_HEADER_OFFSET_ORIGIN 24u
PLANNER_STATIC_ASSERT(sizeof(planner_v1_map_header) == PLANNER_V1_MAP_HEADER_SIZE, "planner_v1_map_header size");
PLANNER_STATIC_ASSERT(PLANNER_ALIGNOF(planner_v1_map_header) == PLANNER_V1_MAP_HEADER_ALIGN, "planner_v1_map_header alignment");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, wire_version) == PLANNER_V1_MAP_HEADER_OFFSET_WIRE_VERSION, "planner_v1_map_header.wire_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, layout) == PLANNER_V1_MAP_HEADER_OFFSET_LAYOUT, "planner_v1_map_header.layout");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, reserved) == PLANNER_V1_MAP_HEADER_OFFSET_RESERVED, "planner_v1_map_header.reserved");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, map_id) == PLANNER_V1_MAP_HEADER_OFFSET_MAP_ID, "planner_v1_map_header.map_id");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, map_version) == PLANNER_V1_MAP_HEADER_OFFSET_MAP_VERSION, "planner_v1_map_header.map_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, width) == PLANNER_V1_MAP_HEADER_OFFSET_WIDTH, "planner_v1_map_header.width");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, height) == PLANNER_V1_MAP_HEADER_OFFSET_HEIGHT, "planner_v1_map_header.height");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, resolution) == PLANNER_V1_MAP_HEADER_OFFSET_RESOLUTION, "planner_v1_map_header.resolution");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_map_header, origin) == PLANNER_V1_MAP_HEADER_OFFSET_ORIGIN, "planner_v1_map_header.origin");

/* planner_v1_plan_params (Rust: planner_ipc::wire::PlanParams) */
typedef struct planner_v1_plan_params {
    float radius;
    uint32_t population;
    uint32_t iterations;
    uint32_t stagnation;
    float clearance;
    float clearance_weight;
    float turn_weight;
    uint8_t guide;
    uint8_t reserved[3];
} planner_v1_plan_params;
#define PLANNER_V1_PLAN_PARAMS_SIZE 32u
#define PLANNER_V1_PLAN_PARAMS_ALIGN 4u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_RADIUS 0u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_POPULATION 4u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_ITERATIONS 8u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_STAGNATION 12u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_CLEARANCE 16u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_CLEARANCE_WEIGHT 20u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_TURN_WEIGHT 24u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_GUIDE 28u
#define PLANNER_V1_PLAN_PARAMS_OFFSET_RESERVED 29u
PLANNER_STATIC_ASSERT(sizeof(planner_v1_plan_params) == PLANNER_V1_PLAN_PARAMS_SIZE, "planner_v1_plan_params size");
PLANNER_STATIC_ASSERT(PLANNER_ALIGNOF(planner_v1_plan_params) == PLANNER_V1_PLAN_PARAMS_ALIGN, "planner_v1_plan_params alignment");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, radius) == PLANNER_V1_PLAN_PARAMS_OFFSET_RADIUS, "planner_v1_plan_params.radius");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, population) == PLANNER_V1_PLAN_PARAMS_OFFSET_POPULATION, "planner_v1_plan_params.population");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, iterations) == PLANNER_V1_PLAN_PARAMS_OFFSET_ITERATIONS, "planner_v1_plan_params.iterations");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, stagnation) == PLANNER_V1_PLAN_PARAMS_OFFSET_STAGNATION, "planner_v1_plan_params.stagnation");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, clearance) == PLANNER_V1_PLAN_PARAMS_OFFSET_CLEARANCE, "planner_v1_plan_params.clearance");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, clearance_weight) == PLANNER_V1_PLAN_PARAMS_OFFSET_CLEARANCE_WEIGHT, "planner_v1_plan_params.clearance_weight");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, turn_weight) == PLANNER_V1_PLAN_PARAMS_OFFSET_TURN_WEIGHT, "planner_v1_plan_params.turn_weight");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, guide) == PLANNER_V1_PLAN_PARAMS_OFFSET_GUIDE, "planner_v1_plan_params.guide");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_params, reserved) == PLANNER_V1_PLAN_PARAMS_OFFSET_RESERVED, "planner_v1_plan_params.reserved");

/* planner_v1_plan_request (Rust: planner_ipc::wire::PlanRequest) */
typedef struct planner_v1_plan_request {
    uint16_t wire_version;
    uint8_t kind;
    uint8_t algorithm;
    uint32_t reserved;
    uint64_t request_id;
    uint64_t seed;
    uint64_t deadline_us;
    uint64_t wake_token;
    uint64_t polls_until_ns;
    uint32_t map_id;
    uint32_t map_version;
    int32_t start[2];
    int32_t goal[2];
    planner_v1_plan_params params;
} planner_v1_plan_request;
#define PLANNER_V1_PLAN_REQUEST_SIZE 104u
#define PLANNER_V1_PLAN_REQUEST_ALIGN 8u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_WIRE_VERSION 0u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_KIND 2u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_ALGORITHM 3u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_RESERVED 4u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_REQUEST_ID 8u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_SEED 16u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_DEADLINE_US 24u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_WAKE_TOKEN 32u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_POLLS_UNTIL_NS 40u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_MAP_ID 48u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_MAP_VERSION 52u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_START 56u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_GOAL 64u
#define PLANNER_V1_PLAN_REQUEST_OFFSET_PARAMS 72u
PLANNER_STATIC_ASSERT(sizeof(planner_v1_plan_request) == PLANNER_V1_PLAN_REQUEST_SIZE, "planner_v1_plan_request size");
PLANNER_STATIC_ASSERT(PLANNER_ALIGNOF(planner_v1_plan_request) == PLANNER_V1_PLAN_REQUEST_ALIGN, "planner_v1_plan_request alignment");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, wire_version) == PLANNER_V1_PLAN_REQUEST_OFFSET_WIRE_VERSION, "planner_v1_plan_request.wire_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, kind) == PLANNER_V1_PLAN_REQUEST_OFFSET_KIND, "planner_v1_plan_request.kind");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, algorithm) == PLANNER_V1_PLAN_REQUEST_OFFSET_ALGORITHM, "planner_v1_plan_request.algorithm");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, reserved) == PLANNER_V1_PLAN_REQUEST_OFFSET_RESERVED, "planner_v1_plan_request.reserved");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, request_id) == PLANNER_V1_PLAN_REQUEST_OFFSET_REQUEST_ID, "planner_v1_plan_request.request_id");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, seed) == PLANNER_V1_PLAN_REQUEST_OFFSET_SEED, "planner_v1_plan_request.seed");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, deadline_us) == PLANNER_V1_PLAN_REQUEST_OFFSET_DEADLINE_US, "planner_v1_plan_request.deadline_us");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, wake_token) == PLANNER_V1_PLAN_REQUEST_OFFSET_WAKE_TOKEN, "planner_v1_plan_request.wake_token");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, polls_until_ns) == PLANNER_V1_PLAN_REQUEST_OFFSET_POLLS_UNTIL_NS, "planner_v1_plan_request.polls_until_ns");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, map_id) == PLANNER_V1_PLAN_REQUEST_OFFSET_MAP_ID, "planner_v1_plan_request.map_id");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, map_version) == PLANNER_V1_PLAN_REQUEST_OFFSET_MAP_VERSION, "planner_v1_plan_request.map_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, start) == PLANNER_V1_PLAN_REQUEST_OFFSET_START, "planner_v1_plan_request.start");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, goal) == PLANNER_V1_PLAN_REQUEST_OFFSET_GOAL, "planner_v1_plan_request.goal");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_request, params) == PLANNER_V1_PLAN_REQUEST_OFFSET_PARAMS, "planner_v1_plan_request.params");

/* planner_v1_plan_response_header (Rust: planner_ipc::wire::PlanResponseHeader) */
typedef struct planner_v1_plan_response_header {
    uint16_t wire_version;
    uint16_t status;
    uint8_t algorithm;
    uint8_t kind;
    uint8_t reserved[2];
    uint64_t request_id;
    uint32_t map_id;
    uint32_t map_version;
    uint32_t held_version;
    uint32_t map_width;
    uint32_t map_height;
    uint32_t waypoints;
    float length;
    uint32_t turns;
    uint32_t evaluations;
    float time_us;
    float map_decode_us;
    uint32_t reserved_end;
    uint64_t max_cells;
} planner_v1_plan_response_header;
#define PLANNER_V1_PLAN_RESPONSE_HEADER_SIZE 72u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_ALIGN 8u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_WIRE_VERSION 0u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_STATUS 2u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_ALGORITHM 4u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_KIND 5u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_RESERVED 6u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_REQUEST_ID 8u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_ID 16u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_VERSION 20u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_HELD_VERSION 24u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_WIDTH 28u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_HEIGHT 32u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_WAYPOINTS 36u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_LENGTH 40u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_TURNS 44u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_EVALUATIONS 48u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_TIME_US 52u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_DECODE_US 56u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_RESERVED_END 60u
#define PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAX_CELLS 64u
PLANNER_STATIC_ASSERT(sizeof(planner_v1_plan_response_header) == PLANNER_V1_PLAN_RESPONSE_HEADER_SIZE, "planner_v1_plan_response_header size");
PLANNER_STATIC_ASSERT(PLANNER_ALIGNOF(planner_v1_plan_response_header) == PLANNER_V1_PLAN_RESPONSE_HEADER_ALIGN, "planner_v1_plan_response_header alignment");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, wire_version) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_WIRE_VERSION, "planner_v1_plan_response_header.wire_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, status) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_STATUS, "planner_v1_plan_response_header.status");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, algorithm) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_ALGORITHM, "planner_v1_plan_response_header.algorithm");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, kind) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_KIND, "planner_v1_plan_response_header.kind");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, reserved) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_RESERVED, "planner_v1_plan_response_header.reserved");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, request_id) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_REQUEST_ID, "planner_v1_plan_response_header.request_id");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, map_id) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_ID, "planner_v1_plan_response_header.map_id");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, map_version) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_VERSION, "planner_v1_plan_response_header.map_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, held_version) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_HELD_VERSION, "planner_v1_plan_response_header.held_version");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, map_width) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_WIDTH, "planner_v1_plan_response_header.map_width");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, map_height) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_HEIGHT, "planner_v1_plan_response_header.map_height");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, waypoints) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_WAYPOINTS, "planner_v1_plan_response_header.waypoints");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, length) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_LENGTH, "planner_v1_plan_response_header.length");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, turns) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_TURNS, "planner_v1_plan_response_header.turns");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, evaluations) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_EVALUATIONS, "planner_v1_plan_response_header.evaluations");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, time_us) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_TIME_US, "planner_v1_plan_response_header.time_us");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, map_decode_us) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAP_DECODE_US, "planner_v1_plan_response_header.map_decode_us");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, reserved_end) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_RESERVED_END, "planner_v1_plan_response_header.reserved_end");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_plan_response_header, max_cells) == PLANNER_V1_PLAN_RESPONSE_HEADER_OFFSET_MAX_CELLS, "planner_v1_plan_response_header.max_cells");

/* planner_v1_waypoint (Rust: planner_ipc::wire::Waypoint) */
typedef struct planner_v1_waypoint {
    float x;
    float y;
} planner_v1_waypoint;
#define PLANNER_V1_WAYPOINT_SIZE 8u
#define PLANNER_V1_WAYPOINT_ALIGN 4u
#define PLANNER_V1_WAYPOINT_OFFSET_X 0u
#define PLANNER_V1_WAYPOINT_OFFSET_Y 4u
PLANNER_STATIC_ASSERT(sizeof(planner_v1_waypoint) == PLANNER_V1_WAYPOINT_SIZE, "planner_v1_waypoint size");
PLANNER_STATIC_ASSERT(PLANNER_ALIGNOF(planner_v1_waypoint) == PLANNER_V1_WAYPOINT_ALIGN, "planner_v1_waypoint alignment");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_waypoint, x) == PLANNER_V1_WAYPOINT_OFFSET_X, "planner_v1_waypoint.x");
PLANNER_STATIC_ASSERT(offsetof(planner_v1_waypoint, y) == PLANNER_V1_WAYPOINT_OFFSET_Y, "planner_v1_waypoint.y");

#endif /* PLANNER_WIRE_V1_H */
