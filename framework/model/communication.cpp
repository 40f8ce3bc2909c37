#include "framework/model/communication.hpp"

namespace rockdem {

Communication& serial_communication() {
  static Communication serial;
  return serial;
}

}  // namespace rockdem
