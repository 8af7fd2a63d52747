"""Layer 3, output: files written whole, output folders, text and mathematics, plots, the viewer.

It may import the layers below (base, core, tools); never grading, teaching or the command line.

=========================  =========================================================================================
module                     job
=========================  =========================================================================================
``io``                     writing a file whole or not at all (the one way we write)
``folders``                a command's files in a folder that holds other things (a manifest)
``render``                 tables, Markdown, LaTeX and strict JSON as text
``page``                   every HTML page: one template, one stylesheet, LaTeX as MathML
``urdf_writer``            the identified URDF: the input's text with inertials and dynamics replaced
``xml_spans``              where each element and attribute of a URDF's text is, from the XML parser's own positions
``identification_report``  the identification's report folder
``plotting``               figures of simulations and torques (matplotlib)
``viewer``                 meshcat scenes, animations and offline HTML
=========================  =========================================================================================
"""

__all__ = []
