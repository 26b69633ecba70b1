// Snapshots' contacts -> contacts_t on IGMS_CONTACTS, on the steps they are
// due. Encodes into a preallocated buffer (no allocation per message). Runs on
// the publishing thread only.
#pragma once

#include <vector>

#include "bus/signed_publisher.h"
#include "channels.h"
#include "igms/contacts_t.hpp"
#include "server/loop/snapshot.h"

namespace igms {

// Steps between two contact messages for a scene stepping at rate_hz, sending
// at most contact_rate_hz (0: never; a rate at or above the step rate: every step).
int contactPeriodSteps(double rate_hz, double contact_rate_hz);

class ContactPublisher {
 public:
  // rows: the snapshots' contact rows (0: the scene has no contact, nothing is sent).
  ContactPublisher(bus::SignedPublisher& bus, int rows);
  void publish(const Snapshot& s);
  int64_t sent() const { return sent_; }

 private:
  bus::SignedPublisher& bus_;
  const std::string channel_{channels::kContacts};
  contacts_t msg_;
  std::vector<uint8_t> buffer_;
  int64_t sent_ = 0;
};

}  // namespace igms
