"""DIS PDUs built with PyPI opendis, an implementation independent of ours, for the tests that
send them (opendis_entity_state.py, gateway_test.py). Each works around opendis 1.0's defaults
(docs/dis.md "Outside peers"). Importing this module raises ImportError without opendis."""
from io import BytesIO

from opendis.DataOutputStream import DataOutputStream
from opendis.dis7 import EntityStatePdu


def entity_state(exercise, entity, ecef, algorithm, orientation=(0.0, 0.0, 0.0),
                 velocity=(0.0, 0.0, 0.0), marking=b"OUTSIDE"):
    """The 144 bytes of a land platform's Entity State (kind 1, domain 1, country 222, force 2):
    entity is (site, application, number), ecef and velocity geocentric metres (per second),
    orientation DIS's (psi, theta, phi) in radians, algorithm the dead-reckoning algorithm."""
    es = EntityStatePdu()
    # opendis 1.0: a default PDU serialises with PDU type 0 and family 0.
    es.pduType, es.protocolFamily, es.protocolVersion = 1, 1, 7
    es.exerciseID = exercise
    # ... its PDU status is an object written as a byte (struct.error): use the plain byte.
    es.pduStatus = 0
    # ... appearance and capabilities default to bytes b'0000' (struct.error): use integers.
    es.entityAppearance, es.capabilities = 0, 0
    es.entityID.siteID, es.entityID.applicationID, es.entityID.entityID = entity
    es.forceId = 2
    es.entityType.entityKind, es.entityType.domain, es.entityType.country = 1, 1, 222
    es.entityLocation.x, es.entityLocation.y, es.entityLocation.z = ecef
    es.entityOrientation.psi, es.entityOrientation.theta, es.entityOrientation.phi = orientation
    (es.entityLinearVelocity.x, es.entityLinearVelocity.y,
     es.entityLinearVelocity.z) = velocity
    es.deadReckoningParameters.deadReckoningAlgorithm = algorithm
    # ... the marking's character set defaults to 0 (unspecified): say ASCII.
    es.marking.characterSet = 1
    es.marking.characters = list(marking) + [0] * (11 - len(marking))
    # ... and the length field is left 0: set it to the PDU's size.
    es.length = 144
    buffer = BytesIO()
    es.serialize(DataOutputStream(buffer))
    return buffer.getvalue()
