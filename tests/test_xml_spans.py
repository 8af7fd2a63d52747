"""course_dynamics/output/xml_spans.py: elements and attribute values found where the parser says they are."""
from __future__ import annotations

import pytest

from course_dynamics.base.errors import InputError
from course_dynamics.output.xml_spans import elements


def value(raw: bytes, element, name: str) -> bytes:
    return raw[slice(*element.attributes[name])]


def test_attribute_values_are_the_text_between_their_own_quotes():
    raw = (b"<robot>\n<!-- <joint damping='1'/> --><![CDATA[<joint damping='2'/>]]><?pi damping='3'?>\n"
           b"<joint note='damping=\"4\" a>b' x:damping=\"5\" xmlns:x=\"urn:x\"\r\n\tdamping\t=\n'&#54;' friction=\"&quot;\"/>"
           b"<link name='l'><inertial/></link ></robot>")
    root = elements(raw, "t.urdf")
    joint, link = root.children
    assert (joint.name, joint.empty, raw[joint.start:joint.end].endswith(b"\"&quot;\"/>")) == ("joint", True, True)
    assert value(raw, joint, "damping") == b"&#54;" and value(raw, joint, "note") == b'damping="4" a>b'
    assert value(raw, joint, "friction") == b"&quot;" and joint.values["friction"] == '"'
    assert set(joint.attributes) == {"note", "damping", "friction"}          # x:damping is another attribute
    assert raw[link.end_tag:link.end] == b"</link >" and link.children[0].name == "inertial"


def test_a_namespace_is_seen_as_a_namespace_aware_reader_sees_it():
    raw = b'<r xmlns:x="urn:x"><x:dynamics/><dynamics xmlns="urn:y"/><dynamics/></r>'
    prefixed, defaulted, plain = elements(raw, "t.urdf").children
    assert [e.name for e in (prefixed, defaulted, plain)] == ["urn:x dynamics", "urn:y dynamics", "dynamics"]
    assert [e.default_namespace for e in (prefixed, defaulted, plain)] == [False, True, False]


@pytest.mark.parametrize("raw, fragment", [
    (b'<!DOCTYPE r [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;&a;&a;">]><r n="&b;"/>', "DTD or an entity"),   # laughs
    (b'<!DOCTYPE r SYSTEM "file:///etc/passwd"><r/>', "DTD or an entity"),                              # XXE
    (b'<r n="&undeclared;"/>', "malformed XML"),
    (b'<?xml version="1.0" encoding="Shift_JIS"?><r/>', "save it as UTF-8"),
    (b'<?xml version="1.0" encoding="no-such-encoding"?><r/>', "save it as UTF-8"),
    (b"<r><a></r>", "malformed XML"),
])
def test_what_cannot_be_edited_in_place_is_one_line(raw, fragment):
    with pytest.raises(InputError) as error:
        elements(raw, "t.urdf")
    assert str(error.value).startswith("t.urdf: ") and fragment in str(error.value) and "\n" not in str(error.value)
