// Channel names and the default LCM URL: the one place they are spelled.
#pragma once

namespace igms::channels {

// ttl=0 (LCM's default, written out): nothing leaves this machine. Processes
// that open it run inside scripts/netns_run.sh so that IGMP joins stay local too.
inline constexpr const char* kDefaultUrl = "udpm://239.255.76.67:7667?ttl=0";

inline constexpr const char* kHapticInput = "IGMS_HAPTIC_INPUT";       // haptic_input_t
inline constexpr const char* kRobotState = "IGMS_ROBOT_STATE";         // robot_state_t
// With fault injection on, every state also goes here, undropped, so a log of
// a lossy session still re-simulates.
inline constexpr const char* kRobotStateTruth = "IGMS_ROBOT_STATE_TRUTH";  // robot_state_t
inline constexpr const char* kCommand = "IGMS_COMMAND";                // command_t
inline constexpr const char* kServerStatus = "IGMS_SERVER_STATUS";     // server_status_t
inline constexpr const char* kEditedTrajectory = "IGMS_TRAJECTORY_EDITED";  // trajectory_t
inline constexpr const char* kClientStatus = "IGMS_CLIENT_STATUS";     // client_status_t
inline constexpr const char* kSessionInfo = "IGMS_SESSION_INFO";       // session_info_t
// With each session info: every robot's model and trajectory file, every mesh's hash.
inline constexpr const char* kSessionFiles = "IGMS_SESSION_FILES";     // session_files_t
inline constexpr const char* kHeartbeat = "IGMS_HEARTBEAT";            // heartbeat_t
// Scenes with contact: points, normals and forces, at most --contact-rate Hz.
inline constexpr const char* kContacts = "IGMS_CONTACTS";              // contacts_t
// Every program, 1 Hz: its message checks' counts (bus/message_verifier.h).
inline constexpr const char* kBusStatus = "IGMS_BUS_STATUS";           // bus_status_t
// The haptic client, 1 Hz: its device's call times and the limits it renders to.
inline constexpr const char* kDeviceStatus = "IGMS_DEVICE_STATUS";     // device_status_t

}  // namespace igms::channels
