// Interim: the cell list replaces this; until then detection is the brute-force reference.
#include "unjam/contacts/contact.hpp"

namespace unjam {

std::vector<Contact> DetectContacts(const Scene& scene, double margin) {
  return DetectContactsBruteForce(scene, margin);
}

}  // namespace unjam
