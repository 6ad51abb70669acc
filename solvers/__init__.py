"""y"""
VALUE = 1
